#pragma once
// An open link to one drive (Python: lmcfg.Drive, a context manager): its
// operations run without the GIL, one at a time, with the cancel flag the
// callbacks and signals set. bind_link.cpp opens it, bind_drive.cpp binds it.
#include <map>
#include <memory>
#include <mutex>
#include <vector>

#include "bindings.hpp"
#include "common/layers.hpp"
#include "config/config_io.hpp"
#include "db/database.hpp"
#include "link/session.hpp"
#include "link/spec.hpp"
#include "ops/backup.hpp"
#include "ops/recovery.hpp"
#include "ops/restore_run.hpp"

namespace lmcfg::python {

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

}  // namespace lmcfg::python
