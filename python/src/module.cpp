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
#include <pybind11/operators.h>
#include <pybind11/pybind11.h>
#include <pybind11/stl.h>
#include <pybind11/stl/filesystem.h>

#include <atomic>
#include <mutex>
#include <optional>

#include "common/bytes.hpp"
#include "common/layers.hpp"
#include "common/result.hpp"
#include "common/types.hpp"
#include "config/config_io.hpp"
#include "db/database.hpp"
#include "link/session.hpp"
#include "link/spec.hpp"
#include "ops/backup.hpp"
#include "ops/diff.hpp"
#include "ops/recovery.hpp"
#include "ops/restore.hpp"
#include "ops/restore_run.hpp"
#include "sim/state_file.hpp"

namespace py = pybind11;
using namespace lmcfg;

namespace {

// ---------------------------------------------------------------------------
// Exceptions: one class per ErrorClass under lmcfg.Error. The classes live for
// the whole process (module objects are never unloaded), so plain handles.
struct Exceptions {
  py::handle base, invalid_input, plan_refused, link_error, drive_refused, verify_mismatch,
      interrupted;
};
Exceptions& exceptions() {
  static Exceptions e;
  return e;
}

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

// Raises the exception for `e` with `attrs` set on it. Needs the GIL.
[[noreturn]] void raise(const Error& e, const py::dict& attrs = py::dict()) {
  const py::handle cls = class_for(e);
  py::object exc = cls(e.message);
  for (auto item : attrs) exc.attr(item.first) = item.second;
  PyErr_SetObject(cls.ptr(), exc.ptr());
  throw py::error_already_set();
}

template <typename T>
T value_or_raise(Result<T>&& r) {
  if (!r.ok()) raise(r.error());
  return std::move(r).value();
}
void ok_or_raise(const Result<void>& r) {
  if (!r.ok()) raise(r.error());
}

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

ops::Progress progress_of(CallbackGuard* g) {
  return [g](const std::string& phase, std::size_t done, std::size_t total) {
    g->call_progress(phase, done, total);
  };
}

// The database a call uses: the one given, else the package's `lmcfg.db`
// (python/lmcfg/__init__.py opens it at import). Returned as an object, so a
// call that releases the GIL keeps it alive.
py::object database_or_default(py::object given) {
  if (!given.is_none()) return given;
  return py::module_::import("lmcfg").attr("db");
}

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

// ---------------------------------------------------------------------------
// An open link to one drive (Python: lmcfg.Drive, a context manager).
class Drive {
 public:
  Drive(std::unique_ptr<link::Session> s, std::string port, py::object db)
      : session_(std::move(s)), port_(std::move(port)), db_(std::move(db)) {}
  Drive(const Drive&) = delete;
  Drive& operator=(const Drive&) = delete;

  const db::Database& database() const { return db_.cast<const db::Database&>(); }

  // Runs `op(client)` without the GIL, one operation at a time per drive, with
  // the cancel flag and the long-wait callback of `g`.
  template <typename Op>
  auto run(CallbackGuard& g, Op&& op) {
    if (!session_) raise(Error(Errc::invalid_argument, "the drive's link is closed"));
    g.cancel = &cancel_;
    py::gil_scoped_release nogil;
    std::lock_guard lock(busy_);
    cancel_.store(false);
    auto& c = session_->client();
    auto saved = c.options();
    auto opt = saved;
    opt.cancel = &cancel_;
    CallbackGuard* gp = &g;
    opt.on_long_wait = [gp](const std::string&, transport::Millis) {
      py::gil_scoped_acquire gil;
      gp->check_signals();
    };
    c.set_options(opt);
    auto result = op(*session_);
    // The options as the operation left them (relink may have changed ID and
    // checksum), without this call's callbacks.
    auto after = c.options();
    after.cancel = nullptr;
    after.on_long_wait = saved.on_long_wait;
    c.set_options(after);
    return result;
  }

  config::DriveConfig backup(const std::vector<std::string>& layers, bool curves,
                             bool command_table, bool full, bool describe,
                             const std::map<std::string, std::string>& labels,
                             py::object progress) {
    ops::BackupOptions bo;
    bo.layers = {false, false, false, false};
    for (const auto& name : layers) {
      auto l = layers::from_name(name);
      if (!l)
        raise(Error(Errc::invalid_argument,
                    "layers: '" + name + "' is not one of os, mc, intf, appl"));
      bo.layers[static_cast<std::size_t>(*l - 1)] = true;
    }
    bo.curves = curves;
    bo.command_table = command_table;
    bo.full = full;
    bo.ask_drive = describe;
    CallbackGuard g{std::move(progress), py::none()};
    bo.progress = progress_of(&g);
    const auto& db = database();
    auto cfg = run(g, [&](link::Session& s) { return ops::backup(s.client(), bo, db); });
    g.rethrow_if_failed();
    auto out = value_or_raise(std::move(cfg));
    out.identity.link = session_->link_settings();
    out.identity.labels = labels;
    return out;
  }

  ops::Plan plan_restore(const config::DriveConfig& file, bool default_first, bool include_comm,
                         py::object progress) {
    ops::RestoreOptions ro;
    ro.default_first = default_first;
    ro.include_comm = include_comm;
    CallbackGuard g{std::move(progress), py::none()};
    ro.progress = progress_of(&g);
    const auto& db = database();
    auto plan =
        run(g, [&](link::Session& s) { return ops::plan_restore(s.client(), file, db, ro); });
    g.rethrow_if_failed();
    return value_or_raise(std::move(plan));
  }

  ops::RestoreOutcome restore(const config::DriveConfig& file, bool yes, py::object confirm,
                              bool dry_run, bool default_first, bool include_comm, bool reset,
                              bool recovery, py::object progress) {
    ops::RestoreRunOptions ro;
    ro.restore.default_first = default_first;
    ro.restore.include_comm = include_comm;
    ro.restore.reset_after = reset;
    ro.restore.port = port_;
    if (recovery) {
      auto path = ops::recovery_path("restore", port_, session_->client().options().id);
      ro.restore.recovery_path = value_or_raise(std::move(path));
    }
    ro.dry_run = dry_run;
    CallbackGuard g{std::move(progress), std::move(confirm)};
    ro.restore.progress = progress_of(&g);
    CallbackGuard* gp = &g;
    ro.confirm = [gp, yes](const ops::Plan& plan) -> Result<ops::Consent> {
      if (yes) return ops::Consent::go;
      py::gil_scoped_acquire gil;
      if (gp->confirm.is_none())
        return Error(Errc::invalid_argument,
                     "restore writes to the drive: pass yes=True or a confirm callback "
                     "(dry_run=True only plans)");
      try {
        const bool go = py::bool_(gp->confirm(py::cast(plan)));
        return go ? ops::Consent::go : ops::Consent::declined;
      } catch (py::error_already_set& e) {
        gp->error.emplace(std::move(e));
        return Error(Errc::interrupted, "the confirm callback raised");
      }
    };
    const auto& db = database();
    auto out = run(g, [&](link::Session& s) { return ops::run_restore(s, file, db, ro); });
    g.rethrow_if_failed();
    using S = ops::RestoreOutcome::Stage;
    if (out.stage == S::failed) {
      py::dict attrs;
      attrs["outcome"] = py::cast(out);
      raise(*out.error, attrs);
    }
    if (out.stage == S::plan_refused) {
      py::dict attrs;
      attrs["plan"] = py::cast(out.plan);
      attrs["problems"] = py::cast(out.plan.problems);
      attrs["outcome"] = py::cast(out);
      std::string msg = "restore plan refused: ";
      for (std::size_t i = 0; i < out.plan.problems.size(); ++i)
        msg += (i ? "; " : "") + out.plan.problems[i];
      raise(Error(Errc::plan_refused, msg), attrs);
    }
    if (out.stage == S::verify_mismatch) {
      py::dict attrs;
      attrs["mismatches"] = py::cast(out.mismatches);
      attrs["outcome"] = py::cast(out);
      std::string msg =
          "verification found " + std::to_string(out.mismatches.size()) + " mismatch(es): ";
      for (std::size_t i = 0; i < out.mismatches.size(); ++i)
        msg += (i ? "; " : "") + out.mismatches[i];
      raise(Error(Errc::verify_mismatch, msg), attrs);
    }
    return out;
  }

  void close() {
    if (!session_) return;
    Result<void> r;
    {
      py::gil_scoped_release nogil;
      std::lock_guard lock(busy_);
      r = session_->close();
      session_.reset();
    }
    ok_or_raise(r);
  }

  link::Session& session() {
    if (!session_) raise(Error(Errc::invalid_argument, "the drive's link is closed"));
    return *session_;
  }
  const std::string& port() const { return port_; }

 private:
  std::unique_ptr<link::Session> session_;
  std::string port_;
  py::object db_;
  std::mutex busy_;
  std::atomic<bool> cancel_{false};
};

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

// ---------------------------------------------------------------------------
// Configurations.
std::optional<config::FileFormat> format_arg(const std::optional<std::string>& name) {
  if (!name) return std::nullopt;
  return value_or_raise(config::format_from_name(*name));
}

config::WriteOptions write_options(const db::Database& db,
                                   std::optional<ops::DatabaseCtDecoder>& decoder) {
  config::WriteOptions wo;
  if (!db.is_empty()) wo.ct_decoder = &decoder.emplace(db);
  return wo;
}

// A parameter of a configuration with the layer it belongs to.
struct LayerParameter {
  int layer = 0;
  config::Parameter p;
};

std::vector<LayerParameter> parameters_of(const config::DriveConfig& c) {
  std::vector<LayerParameter> out;
  for (std::size_t i = 0; i < c.layers.size(); ++i)
    for (const auto& p : c.layers[i]) out.push_back({static_cast<int>(i + 1), p});
  return out;
}

py::bytes bytes_of(const Bytes& b) {
  return py::bytes(reinterpret_cast<const char*>(b.data()), b.size());
}

// Two files: a default neither the database nor a file records stays unknown
// (the tool asks a connected drive only when a side is `drive`).
std::optional<std::uint32_t> no_default(std::uint16_t) { return std::nullopt; }

std::string layer_name(int layer) { return std::string(layers::name(layer)); }

}  // namespace

PYBIND11_MODULE(_lmcfg, m) {
  m.doc() =
      "lmcfg's C++ library for Python: back up, diff and restore LinMot drive configurations "
      "over LinRS. Use the package `lmcfg`, which re-exports this module.";
  // sim:STATE.json, the built-in simulated drive, as the lmcfg program registers it.
  link::register_scheme("sim", sim::state_file_link_factory());

  // Exceptions (exit codes: README "Exit codes").
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

  // --- database ------------------------------------------------------------
  py::class_<db::Parameter>(m, "DbParameter", "A UPID as the UPID database describes it.")
      .def_readonly("upid", &db::Parameter::upid)
      .def_readonly("name", &db::Parameter::name)
      .def_readonly("path", &db::Parameter::path)
      .def_readonly("description", &db::Parameter::description)
      .def_readonly("comm", &db::Parameter::comm)
      .def_readonly("default", &db::Parameter::default_value)
      .def_property_readonly(
          "layer", [](const db::Parameter& p) { return std::string(db::layer_name(p.layer)); })
      .def_property_readonly("unit", [](const db::Parameter& p) { return p.spec.unit; })
      .def_property_readonly("scale", [](const db::Parameter& p) { return p.spec.scale; })
      .def_property_readonly("min", [](const db::Parameter& p) { return p.spec.min; })
      .def_property_readonly("max", [](const db::Parameter& p) { return p.spec.max; })
      .def_property_readonly("type",
                             [](const db::Parameter& p) -> std::optional<std::string> {
                               if (!p.spec.type) return std::nullopt;
                               return std::string(type_name(*p.spec.type));
                             })
      .def_property_readonly("labels",
                             [](const db::Parameter& p) {
                               std::map<std::int64_t, std::string> out;
                               for (const auto& l : p.spec.labels) out[l.raw] = l.label;
                               return out;
                             })
      .def(
          "format", [](const db::Parameter& p, std::uint32_t raw) { return p.format(raw); },
          py::arg("raw"), "A raw value for people: scaled with unit, or its enum label.")
      .def("__repr__", [](const db::Parameter& p) {
        return "<DbParameter " + hex(p.upid, 4) + "h " + p.name + ">";
      });

  py::class_<db::ErrorEntry>(m, "DbError", "An error code as the UPID database describes it.")
      .def_readonly("domain", &db::ErrorEntry::domain)
      .def_readonly("code", &db::ErrorEntry::code)
      .def_readonly("text", &db::ErrorEntry::text)
      .def_readonly("description", &db::ErrorEntry::description)
      .def_readonly("action", &db::ErrorEntry::action)
      .def_readonly("error_class", &db::ErrorEntry::error_class);

  py::class_<db::Database>(m, "Database",
                           "The UPID database (names, units, types, ranges, labels, error "
                           "texts). An empty one finds nothing.")
      .def(py::init<>(), "An empty database.")
      .def_static(
          "open", [](const std::string& path) { return value_or_raise(db::Database::open(path)); },
          py::arg("path"), "Opens a compiled database (lmcfg-upid.sqlite).")
      .def_property_readonly("is_empty", &db::Database::is_empty)
      .def_property_readonly("path", [](const db::Database& d) { return d.info().path; })
      .def_property_readonly("content_hash",
                             [](const db::Database& d) { return d.info().content_hash; })
      .def(
          "find",
          [](const db::Database& d, std::uint16_t upid) -> std::optional<db::Parameter> {
            const auto* p = d.find(upid);
            if (!p) return std::nullopt;
            return *p;
          },
          py::arg("upid"), "The UPID's description, or None when the database does not know it.")
      .def(
          "parameter",
          [](const db::Database& d, std::uint16_t upid) {
            const auto* p = d.find(upid);
            if (!p)
              throw py::key_error("UPID " + hex(upid, 4) + "h is not in the UPID database" +
                                  (d.is_empty() ? " (no database loaded)" : ""));
            return *p;
          },
          py::arg("upid"), "The UPID's description; KeyError when the database does not know it.")
      .def(
          "search",
          [](const db::Database& d, const std::string& needle) {
            std::vector<db::Parameter> out;
            for (const auto* p : d.search(needle)) out.push_back(*p);
            return out;
          },
          py::arg("text"),
          "Parameters whose name, tree path or description contains `text` (case-insensitive).")
      .def(
          "error",
          [](const db::Database& d, const std::string& domain,
             std::uint32_t code) -> std::optional<db::ErrorEntry> {
            const auto* e = d.error(domain, code);
            if (!e) return std::nullopt;
            return *e;
          },
          py::arg("domain"), py::arg("code"),
          "An error code's entry ('mc', 'linrs', 'devicenet'), or None.");

  // --- configurations --------------------------------------------------------
  py::class_<LayerParameter>(m, "Parameter", "One parameter value of a configuration.")
      .def_readonly("layer", &LayerParameter::layer, "1 OS, 2 MC, 3 Intf, 4 Appl")
      .def_property_readonly("layer_name",
                             [](const LayerParameter& p) { return layer_name(p.layer); })
      .def_property_readonly("upid", [](const LayerParameter& p) { return p.p.upid; })
      .def_property_readonly(
          "value", [](const LayerParameter& p) { return p.p.value; }, "the raw 4-byte value field")
      .def_property_readonly("type", [](const LayerParameter& p) { return p.p.type; })
      .def_property_readonly("default", [](const LayerParameter& p) { return p.p.default_value; })
      .def_property_readonly("name", [](const LayerParameter& p) { return p.p.name; })
      .def_property_readonly("unit", [](const LayerParameter& p) { return p.p.unit; })
      .def_property_readonly("scaled", [](const LayerParameter& p) { return p.p.scaled; })
      .def("__repr__", [](const LayerParameter& p) {
        return "<Parameter " + hex(p.p.upid, 4) + "h " + p.p.name + " = " +
               std::to_string(p.p.value) + ">";
      });

  py::class_<config::Curve>(m, "Curve", "A motion curve (info and data block as read, §11).")
      .def_readonly("id", &config::Curve::id)
      .def_property_readonly("info", [](const config::Curve& c) { return bytes_of(c.info); })
      .def_property_readonly("data", [](const config::Curve& c) { return bytes_of(c.data); });
  py::class_<config::CtEntry>(m, "CtEntry", "A command table entry (raw bytes, §12).")
      .def_readonly("id", &config::CtEntry::id)
      .def_property_readonly("raw", [](const config::CtEntry& e) { return bytes_of(e.raw); });

  py::class_<config::DriveConfig>(
      m, "Config", "A drive configuration: parameters, curves, command table, identity.")
      .def(py::init<>())
      .def_static(
          "load",
          [](const std::filesystem::path& path, std::optional<std::string> format) {
            return value_or_raise(config::read_config_file(path, format_arg(format)));
          },
          py::arg("path"), py::arg("format") = py::none(),
          "Reads a JSON or XML file (format from the extension, else the content).")
      .def_static(
          "loads",
          [](const std::string& text, std::string format, std::string name) {
            return value_or_raise(config::read_config_text(text, name, *format_arg(format)));
          },
          py::arg("text"), py::arg("format") = "json", py::arg("name") = "<string>",
          "Parses JSON or XML text.")
      .def(
          "save",
          [](const config::DriveConfig& c, const std::filesystem::path& path,
             std::optional<std::string> format, py::object db_arg) {
            py::object db = database_or_default(std::move(db_arg));
            std::optional<ops::DatabaseCtDecoder> decoder;
            ok_or_raise(
                config::write_config_file(c, path, format_arg(format),
                                          write_options(db.cast<const db::Database&>(), decoder)));
          },
          py::arg("path"), py::arg("format") = py::none(), py::arg("db") = py::none(),
          "Writes the file atomically (format from the extension unless given).")
      .def(
          "dumps",
          [](const config::DriveConfig& c, std::string format, py::object db_arg) {
            py::object db = database_or_default(std::move(db_arg));
            std::optional<ops::DatabaseCtDecoder> decoder;
            return value_or_raise(config::write_config_text(
                c, *format_arg(format), write_options(db.cast<const db::Database&>(), decoder)));
          },
          py::arg("format") = "json", py::arg("db") = py::none(), "The canonical text of the file.")
      .def_property_readonly("parameters", &parameters_of)
      .def(
          "parameter",
          [](const config::DriveConfig& c, std::uint16_t upid) -> std::optional<LayerParameter> {
            const auto* p = c.find_param(upid);
            if (!p) return std::nullopt;
            return LayerParameter{layers::of_upid(upid), *p};
          },
          py::arg("upid"), "The parameter with this UPID, or None.")
      .def_readonly("curves", &config::DriveConfig::curves)
      .def_readonly("ct_entries", &config::DriveConfig::ct_entries)
      .def_property_readonly("macid", [](const config::DriveConfig& c) { return c.identity.macid; })
      .def_property_readonly("firmware",
                             [](const config::DriveConfig& c) { return c.identity.firmware; })
      .def_property_readonly("captured_at",
                             [](const config::DriveConfig& c) { return c.identity.captured_at; })
      .def_property_readonly("port",
                             [](const config::DriveConfig& c) { return c.identity.link.port; })
      .def_property(
          "labels", [](const config::DriveConfig& c) { return c.identity.labels; },
          [](config::DriveConfig& c, std::map<std::string, std::string> l) {
            c.identity.labels = std::move(l);
          })
      .def_property_readonly(
          "full",
          [](const config::DriveConfig& c) { return c.scope.parameters == config::ParamSet::full; })
      .def(py::self == py::self)
      .def("__repr__", [](const config::DriveConfig& c) {
        std::size_t n = 0;
        for (const auto& l : c.layers) n += l.size();
        return "<Config MACID " + c.identity.macid + ": " + std::to_string(n) + " parameters, " +
               std::to_string(c.curves.size()) + " curves, " + std::to_string(c.ct_entries.size()) +
               " CT entries>";
      });

  // --- diff ----------------------------------------------------------------
  py::class_<ops::DiffItem>(m, "DiffItem", "One difference, as `lmcfg diff --json` lists it.")
      .def_property_readonly("kind", [](const ops::DiffItem& d) { return ops::kind_name(d.kind); })
      .def_readonly("layer", &ops::DiffItem::layer)
      .def_readonly("key", &ops::DiffItem::key,
                    "UPID, curve ID, CT entry ID or DeviceNet command ID")
      .def_property_readonly(
          "upid",
          [](const ops::DiffItem& d) -> std::optional<std::uint32_t> {
            if (d.kind != ops::DiffItem::Kind::parameter) return std::nullopt;
            return d.key;
          },
          "the UPID for a parameter, else None")
      .def_readonly("name", &ops::DiffItem::name)
      .def_readonly("old", &ops::DiffItem::a, "the value on side A, as text")
      .def_readonly("new", &ops::DiffItem::b, "the value on side B, as text")
      .def_readonly("detail", &ops::DiffItem::detail)
      .def_readonly("old_invalid", &ops::DiffItem::a_invalid)
      .def_readonly("new_invalid", &ops::DiffItem::b_invalid)
      .def("__repr__", [](const ops::DiffItem& d) {
        return std::string("<DiffItem ") + ops::kind_name(d.kind) + " " + std::to_string(d.key) +
               " " + d.name + ": " + d.a + " -> " + d.b + ">";
      });
  m.def(
      "diff",
      [](const config::DriveConfig& a, const config::DriveConfig& b, bool ignore_metadata,
         bool ignore_unit, py::object db_arg) {
        py::object db = database_or_default(std::move(db_arg));
        ops::DiffOptions o;
        o.ignore_metadata = ignore_metadata;
        o.ignore_unit = ignore_unit;
        return ops::diff(a, b, db.cast<const db::Database&>(), no_default, o).items;
      },
      py::arg("a"), py::arg("b"), py::arg("ignore_metadata") = false,
      py::arg("ignore_unit") = false, py::arg("db") = py::none(),
      "The differences between two configurations, as `lmcfg diff A B` lists them.");
  m.def(
      "diff_text",
      [](const config::DriveConfig& a, const config::DriveConfig& b, const std::string& a_name,
         const std::string& b_name, bool ignore_metadata, bool ignore_unit, py::object db_arg) {
        py::object db = database_or_default(std::move(db_arg));
        ops::DiffOptions o;
        o.ignore_metadata = ignore_metadata;
        o.ignore_unit = ignore_unit;
        const auto& d = db.cast<const db::Database&>();
        return ops::render_text(ops::diff(a, b, d, no_default, o), a_name, b_name);
      },
      py::arg("a"), py::arg("b"), py::arg("a_name") = "A", py::arg("b_name") = "B",
      py::arg("ignore_metadata") = false, py::arg("ignore_unit") = false,
      py::arg("db") = py::none(), "The difference report `lmcfg diff A B` prints.");

  // --- restore plan and outcome ----------------------------------------------
  py::class_<ops::PlanStep>(m, "PlanStep", "One step of a restore plan.")
      .def_property_readonly("action",
                             [](const ops::PlanStep& s) { return ops::action_name(s.action); })
      .def_readonly("layer", &ops::PlanStep::layer)
      .def_readonly("key", &ops::PlanStep::key)
      .def_readonly("value", &ops::PlanStep::value)
      .def_readonly("old_value", &ops::PlanStep::old_value)
      .def_readonly("text", &ops::PlanStep::text)
      .def_readonly("name", &ops::PlanStep::name)
      .def_readonly("old", &ops::PlanStep::old_display)
      .def_readonly("new", &ops::PlanStep::new_display)
      .def_property_readonly(
          "why", [](const ops::PlanStep& s) { return ops::write_reason_text(s.reason); })
      .def("__repr__", [](const ops::PlanStep& s) {
        return std::string("<PlanStep ") + ops::action_name(s.action) + ": " + s.text + ">";
      });
  py::class_<ops::Plan>(m, "Plan", "A restore plan: what would be written, and any problems.")
      .def_readonly("problems", &ops::Plan::problems)
      .def_readonly("steps", &ops::Plan::steps)
      .def_readonly("skipped", &ops::Plan::skipped)
      .def_readonly("notes", &ops::Plan::notes)
      .def_readonly("losses", &ops::Plan::losses)
      .def_readonly("write_telegrams", &ops::Plan::write_telegrams)
      .def_property_readonly("ok", &ops::Plan::ok)
      .def_property_readonly("nothing_to_do", &ops::Plan::nothing_to_do)
      .def(
          "json", [](const ops::Plan& p) { return ops::plan_json(p).dump(); },
          "The plan as `lmcfg restore --json` reports it (docs/restore.md), a JSON string.")
      .def("__str__", &ops::render_plan);
  py::class_<ops::RestoreOutcome>(m, "RestoreOutcome", "What a restore did.")
      .def_property_readonly("stage",
                             [](const ops::RestoreOutcome& o) { return ops::stage_name(o.stage); })
      .def_readonly("plan", &ops::RestoreOutcome::plan)
      .def_readonly("mismatches", &ops::RestoreOutcome::mismatches)
      .def_readonly("written", &ops::RestoreOutcome::written)
      .def_property_readonly("link_after",
                             [](const ops::RestoreOutcome& o) -> std::optional<std::string> {
                               if (!o.relink || !o.relink->changed) return std::nullopt;
                               return o.relink->summary;
                             })
      .def("__repr__", [](const ops::RestoreOutcome& o) {
        return std::string("<RestoreOutcome ") + ops::stage_name(o.stage) + ">";
      });

  // --- drives ----------------------------------------------------------------
  py::class_<Drive>(m, "Drive",
                    "An open link to one drive. Use it as a context manager: leaving the block "
                    "closes the link (a sim: drive saves its state file).")
      .def(
          "backup",
          [](Drive& d, std::vector<std::string> layers, bool curves, bool command_table, bool full,
             bool describe, std::map<std::string, std::string> labels, py::object progress) {
            return d.backup(layers, curves, command_table, full, describe, labels,
                            std::move(progress));
          },
          py::arg("layers") = std::vector<std::string>{"os", "mc", "intf", "appl"},
          py::arg("curves") = true, py::arg("command_table") = true, py::arg("full") = false,
          py::arg("describe") = true, py::arg("labels") = std::map<std::string, std::string>{},
          py::arg("progress") = py::none(),
          "Reads the drive's configuration (read telegrams only), as `lmcfg backup`.")
      .def("plan_restore", &Drive::plan_restore, py::arg("config"), py::arg("default_first") = true,
           py::arg("include_comm") = false, py::arg("progress") = py::none(),
           "The restore plan for `config` on this drive (reads only). A plan with problems "
           "is returned, not raised: see `.ok` and `.problems`.")
      .def("restore", &Drive::restore, py::arg("config"), py::arg("yes") = false,
           py::arg("confirm") = py::none(), py::arg("dry_run") = false,
           py::arg("default_first") = true, py::arg("include_comm") = false,
           py::arg("reset") = true, py::arg("recovery") = true, py::arg("progress") = py::none(),
           "Plans, writes what differs and verifies, as `lmcfg restore`.")
      .def("close", &Drive::close, "Closes the link (a sim: drive saves its state file).")
      .def_property_readonly("port", &Drive::port)
      .def_property_readonly("describe", [](Drive& d) { return d.session().describe(); })
      .def_property_readonly(
          "telegrams", [](Drive& d) { return d.session().client().stats().requests; },
          "requests sent since the link opened")
      .def("__enter__", [](py::object self) { return self; })
      .def("__exit__", [](Drive& d, py::args) {
        d.close();
        return false;
      });

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
