#pragma once
// What the files of the extension module `_lmcfg` share (python/src/): the
// exceptions a library Error becomes, the guard of Python callbacks during an
// operation without the GIL, the default database, and the bind_* functions
// module.cpp calls, one per group of classes.
#include <pybind11/pybind11.h>

#include <atomic>
#include <optional>
#include <string>

#include "common/result.hpp"
#include "ops/restore.hpp"

namespace py = pybind11;

namespace lmcfg::python {

// ---------------------------------------------------------------------------
// Exceptions: one class per ErrorClass under lmcfg.Error. The classes live for
// the whole process (module objects are never unloaded), so plain handles.
struct Exceptions {
  py::handle base, invalid_input, plan_refused, link_error, drive_refused, verify_mismatch,
      interrupted;
};
Exceptions& exceptions();

// Raises the exception for `e` with `attrs` set on it. Needs the GIL.
[[noreturn]] void raise(const Error& e, const py::dict& attrs = py::dict());

template <typename T>
T value_or_raise(Result<T>&& r) {
  if (!r.ok()) raise(r.error());
  return std::move(r).value();
}
void ok_or_raise(const Result<void>& r);

// ---------------------------------------------------------------------------
// Python callbacks during an operation that runs without the GIL. The
// operation's std::function objects capture only a pointer to this guard (they
// may be copied without the GIL; a py::object must not be). A callback that
// raises, and a pending signal (Ctrl-C: KeyboardInterrupt), set the drive's
// cancel flag: the client stops before its next telegram (the one in flight
// completes), and the Python exception is raised instead of the library's.
struct CallbackGuard {
  CallbackGuard(py::object p, py::object c) : progress(std::move(p)), confirm(std::move(c)) {}
  py::object progress;  // None or callable(phase, done, total)
  py::object confirm;   // None or callable(plan) -> bool
  std::atomic<bool>* cancel = nullptr;
  std::optional<py::error_already_set> error;

  // With the GIL held.
  void check_signals() {
    if (error) return;
    if (PyErr_CheckSignals() != 0) {
      error.emplace();
      cancel->store(true);
    }
  }
  void call_progress(const std::string& phase, std::size_t done, std::size_t total) {
    py::gil_scoped_acquire gil;
    check_signals();
    if (error || progress.is_none()) return;
    try {
      progress(phase, done, total);
    } catch (py::error_already_set& e) {
      error.emplace(std::move(e));
      cancel->store(true);
    }
  }
  void rethrow_if_failed() {
    if (error) {
      auto e = std::move(*error);
      error.reset();
      throw e;
    }
  }
};

inline ops::Progress progress_of(CallbackGuard* g) {
  return [g](const std::string& phase, std::size_t done, std::size_t total) {
    g->call_progress(phase, done, total);
  };
}

// The database a call uses: the one given, else the package's `lmcfg.db`
// (python/lmcfg/__init__.py opens it at import). Returned as an object, so a
// call that releases the GIL keeps it alive.
py::object database_or_default(py::object given);

// The module's classes and functions, in the order module.cpp registers them.
void bind_errors(py::module_& m);
void bind_database(py::module_& m);
void bind_config(py::module_& m);
void bind_diff(py::module_& m);
void bind_restore(py::module_& m);
void bind_drive(py::module_& m);
void bind_link(py::module_& m);

}  // namespace lmcfg::python
