// The extension module `_lmcfg`: the library's operations for Python
// (docs/python.md). The pure-Python package `lmcfg` (python/lmcfg/) re-exports
// it and adds the idioms (Link, the module-level database).
//
// Every call goes through the functions the `lmcfg` tool calls (link::open_session,
// ops::backup, ops::diff, ops::plan_restore, ops::run_restore, config::read/
// write_config_file): the bindings only convert arguments and results. Drive I/O
// runs with the GIL released; Python callbacks (progress, confirm) re-acquire it.
// A library Error becomes the exception of its class (ErrorClass), whose
// `exit_code` is the one the CLI exits with for that class (README "Exit codes").
//
// One file per group of classes (bind_*.cpp); the shared helpers are in
// bindings.hpp, the Drive class in drive.hpp.
#include <pybind11/pybind11.h>

#include "bindings.hpp"
#include "link/port.hpp"
#include "sim/state_file.hpp"

namespace lmcfg::python {

Exceptions& exceptions() {
  static Exceptions e;
  return e;
}

namespace {

py::handle class_for(const Error& e) {
  auto& x = exceptions();
  const auto c = class_of(e.code);
  if (!c) return x.base;  // not classified: an internal error (exit 70)
  switch (*c) {
    case ErrorClass::link_failure:
    case ErrorClass::bad_answer:
    case ErrorClass::link_down:
      return x.link_error;
    case ErrorClass::drive_refusal:
      return x.drive_refused;
    case ErrorClass::bad_input:
      return x.invalid_input;
    case ErrorClass::plan_refused:
      return x.plan_refused;
    case ErrorClass::verify_mismatch:
      return x.verify_mismatch;
    case ErrorClass::interrupted:
      return x.interrupted;
  }
  return x.base;
}

}  // namespace

// Raises the exception for `e` with `attrs` set on it. Needs the GIL.
[[noreturn]] void raise(const Error& e, const py::dict& attrs) {
  const py::handle cls = class_for(e);
  py::object exc = cls(e.message);
  for (auto item : attrs) exc.attr(item.first) = item.second;
  PyErr_SetObject(cls.ptr(), exc.ptr());
  throw py::error_already_set();
}

void ok_or_raise(const Result<void>& r) {
  if (!r.ok()) raise(r.error());
}

// The database a call uses: the one given, else the package's `lmcfg.db`
// (python/lmcfg/__init__.py opens it at import). Returned as an object, so a
// call that releases the GIL keeps it alive.
py::object database_or_default(py::object given) {
  if (!given.is_none()) return given;
  return py::module_::import("lmcfg").attr("db");
}

// Exceptions (exit codes: README "Exit codes").
void bind_errors(py::module_& m) {
  auto make = [&](const char* name, py::handle base, int code, const char* doc) {
    py::handle cls =
        PyErr_NewExceptionWithDoc((std::string("lmcfg.") + name).c_str(), doc, base.ptr(), nullptr);
    if (!cls) throw py::error_already_set();
    cls.attr("exit_code") = code;
    m.add_object(name, cls);
    return cls;
  };
  auto& x = exceptions();
  x.base = make("Error", PyExc_Exception, 70,
                "Base of lmcfg's errors. `exit_code` is the lmcfg program's exit code for the "
                "same failure (70: internal error).");
  x.invalid_input = make("InvalidInput", x.base, 2,
                         "Bad input: a bad file, option value or argument; nothing written.");
  x.plan_refused = make("PlanRefused", x.base, 3,
                        "The restore plan found problems (`problems`, `plan`); nothing written.");
  x.link_error = make("LinkError", x.base, 4,
                      "Communication failure: no answer, link lost, garbled telegrams.");
  x.drive_refused =
      make("DriveRefused", x.base, 5, "The drive refused a request (LinRS error state C1..C9).");
  x.verify_mismatch = make("VerifyMismatch", x.base, 6,
                           "Written, but the drive reads back differently (`mismatches`).");
  x.interrupted = make("Interrupted", x.base, 130,
                       "Stopped between two telegrams; the message names the step reached.");
}

}  // namespace lmcfg::python

PYBIND11_MODULE(_lmcfg, m) {
  using namespace lmcfg;
  using namespace lmcfg::python;
  m.doc() =
      "lmcfg's C++ library for Python: back up, diff and restore LinMot drive configurations "
      "over LinRS. Use the package `lmcfg`, which re-exports this module.";
  // sim:STATE.json, the built-in simulated drive, as the lmcfg program registers it.
  link::register_scheme("sim", sim::state_file_link_factory());

  bind_errors(m);
  bind_database(m);
  bind_config(m);
  bind_diff(m);
  bind_restore(m);
  bind_drive(m);
  bind_link(m);
}
