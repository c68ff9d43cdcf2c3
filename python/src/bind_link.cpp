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

Result<ops::LinkOptions> link_options(const OpenArgs& a) {
  ops::LinkOptions l;
  l.port = a.port;
  l.trace_path = a.trace;
  l.holder = "a Python script (lmcfg module)";  // named to a second program on the port
  l.serial.baud = a.baud;
  l.serial.stop_bits = a.stop_bits;
  LMCFG_ASSIGN_OR_RETURN(l.serial.parity, ops::parse_parity(a.parity));
  LMCFG_TRY(transport::validate(l.serial));
  if (a.id < 0 || a.id > 0xFF)
    return Error(Errc::invalid_argument,
                 "id " + std::to_string(a.id) + " is not a MACID 0..255 (0x00..0xFF)");
  l.client.id = static_cast<std::uint8_t>(a.id);
  LMCFG_ASSIGN_OR_RETURN(l.client.checksum, ops::parse_checksum(a.checksum));
  LMCFG_ASSIGN_OR_RETURN(l.client.checksum.coverage,
                         ops::parse_checksum_coverage(a.checksum_coverage));
  if (a.timeout_ms < 1 || a.timeout_ms > 60000)
    return Error(Errc::invalid_argument,
                 "timeout_ms " + std::to_string(a.timeout_ms) + " is outside 1..60000");
  if (a.retries < 0 || a.retries > 10)
    return Error(Errc::invalid_argument,
                 "retries " + std::to_string(a.retries) + " is outside 0..10");
  if (a.agreeing_reads < 0 || a.agreeing_reads > 5)
    return Error(Errc::invalid_argument, "agreeing_reads " + std::to_string(a.agreeing_reads) +
                                             " is not 0 (automatic) or 1..5");
  l.client.timeout = transport::Millis(a.timeout_ms);
  l.client.read_retries = a.retries;
  l.agreeing_reads = a.agreeing_reads;
  return l;
}

std::unique_ptr<Drive> open_drive(const OpenArgs& a, py::object db_arg) {
  py::object db = database_or_default(std::move(db_arg));
  db.cast<const db::Database&>();  // a wrong type fails here, not in an operation
  auto opt = value_or_raise(link_options(a));
  Result<std::unique_ptr<ops::Session>> s = Error(Errc::not_supported, "not opened");
  {
    py::gil_scoped_release nogil;
    s = ops::open_session(opt);
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
