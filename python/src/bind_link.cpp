// Link options for Python, validated by the functions the tool's options go
// through, and lmcfg.open(): the link to one drive.
#include <pybind11/stl.h>

#include "drive.hpp"

namespace lmcfg::python {

namespace {

// ---------------------------------------------------------------------------
// Link options, validated by the functions the tool's options go through.
struct OpenArgs {
  std::string port;
  unsigned baud = 57600;
  std::string parity = "none";
  unsigned stop_bits = 1;
  int id = 0x11;
  std::string checksum = "none";
  std::string checksum_coverage = "id";
  int timeout_ms = 200;
  int retries = 2;
  int agreeing_reads = 0;
  std::string trace;
};

// The tool's one check (link::make_link_spec), worded with the Python names;
// agreeing_reads 0 is automatic.
Result<link::LinkSpec> link_options(const OpenArgs& a) {
  link::LinkInput in;
  in.port = a.port;
  in.trace = a.trace;
  in.holder = "a Python script (lmcfg module)";  // named to a second program on the port
  in.baud = a.baud;
  in.stop_bits = a.stop_bits;
  in.parity = a.parity;
  in.id = std::to_string(a.id);
  in.checksum = a.checksum;
  in.checksum_coverage = a.checksum_coverage;
  in.timeout_ms = a.timeout_ms;
  in.retries = a.retries;
  in.agreeing_reads = a.agreeing_reads == 0 ? "auto" : std::to_string(a.agreeing_reads);
  return link::make_link_spec(in, link::kPythonNames);
}

std::unique_ptr<Drive> open_drive(const OpenArgs& a, py::object db_arg) {
  py::object db = database_or_default(std::move(db_arg));
  db.cast<const db::Database&>();  // a wrong type fails here, not in an operation
  auto opt = value_or_raise(link_options(a));
  Result<std::unique_ptr<link::Session>> s = Error(Errc::not_supported, "not opened");
  {
    py::gil_scoped_release nogil;
    s = link::open_session(opt);
  }
  return std::make_unique<Drive>(value_or_raise(std::move(s)), a.port, std::move(db));
}

}  // namespace

void bind_link(py::module_& m) {
  m.def(
      "open",
      [](std::string port, unsigned baud, std::string parity, unsigned stop_bits, int id,
         std::string checksum, std::string checksum_coverage, int timeout_ms, int retries,
         int agreeing_reads, std::string trace, py::object db) {
        OpenArgs a{std::move(port),
                   baud,
                   std::move(parity),
                   stop_bits,
                   id,
                   std::move(checksum),
                   std::move(checksum_coverage),
                   timeout_ms,
                   retries,
                   agreeing_reads,
                   std::move(trace)};
        return open_drive(a, std::move(db));
      },
      py::arg("port"), py::arg("baud") = 57600, py::arg("parity") = "none",
      py::arg("stop_bits") = 1, py::arg("id") = 0x11, py::arg("checksum") = "none",
      py::arg("checksum_coverage") = "id", py::arg("timeout_ms") = 200, py::arg("retries") = 2,
      py::arg("agreeing_reads") = 0, py::arg("trace") = "", py::arg("db") = py::none(),
      "Opens the link to one drive (the lmcfg program's link options).");
}

}  // namespace lmcfg::python
