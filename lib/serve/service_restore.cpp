// Restore jobs of the service (docs/serve.md): an API plan executed, an
// automatic restore of a replaced drive, and restores a stopped service left
// unfinished; each through the normal restore, recorded as a commit.
#include <algorithm>

#include "common/bytes.hpp"
#include "config/config_io.hpp"
#include "fleet/history.hpp"
#include "ops/recovery.hpp"
#include "ops/undo.hpp"
#include "report/report.hpp"
#include "serve/console_words.hpp"
#include "serve/service_impl.hpp"

namespace lmcfg::serve {

namespace {

// Who an automatic restore records as its operator, and why.
constexpr const char* kAutomatic = "lmcfg serve (automatic)";
constexpr const char* kReplacedCause = "factory-fresh drive found at the position";
// Who an automatic retry of a failed restore runs as (the job's `asked_by`
// names the operator of the first attempt).
constexpr const char* kRetry = "lmcfg serve (automatic retry)";

// The plan the API showed and the target as a restore reads it now: the
// error that refuses the restore when they differ.
std::optional<Error> plan_changed(const ops::Plan& planned, const ops::Plan& now,
                                  const std::string& plan_id) {
  const std::string what = ops::target_change(planned, now);
  if (what.empty()) return std::nullopt;
  return Error(Errc::plan_refused, "the target changed since plan " + plan_id + " was made (" +
                                       what + "); nothing written: make a new plan");
}

}  // namespace

// Caller holds store's lock. An automatic retry `job` failed with `e`:
// listed on the waiting record and counted.
void Service::Impl::note_retry_failed(const Job& job, const Error& e, PendingRestore& p,
                                      StateStore::Data& data) const {
  p.failures.push_back({iso_time(opt.clock()), job.id, e.message});
  if (p.failures.size() > kRetryFailuresKept) p.failures.erase(p.failures.begin());
  ++p.failed_attempts;
  ++data.states[p.drive].retries_failed;
}

// Runs a restore of `f` on this line's worker thread (the caller is it):
// the normal restore (plan against the target, undo record, execute,
// verify), recorded as a commit with the audit trailers. `planned`: the plan
// the API showed; the target must still read as it found it.
void Service::Impl::run_restore_job(Job& job, std::size_t li, const fleet::ArchivedFile& f,
                                    const ops::Audit& audit, bool skip, const std::string& cause,
                                    const ops::Plan* planned, const std::string& plan_id) {
  const auto& line = opt.inventory.lines[li];
  const auto& d = *f.drive;
  jobs.update(job, [&](Job& j) {
    j.started = true;
    if (planned) j.step_total = planned->steps.size();
  });
  log("restore job " + job.id + ": " + d.name + " <- " + f.file_name + " started" +
      (audit.who.empty() ? "" : " for " + audit.who));
  RestoreAttempt a;
  PendingRestore begun{d.name, f.source.id, audit.who, audit.reason, audit.ticket, cause, skip, "",
                       "",     {},          0};
  begun.origin_job = job.retry_of.empty() ? job.id : job.retry_of;
  // A retry records the operator who asked for the first attempt, not itself.
  if (!job.asked_by.empty()) begun.who = job.asked_by;
  // What the drive is known to hold before this attempt: the waiting
  // retry's record, else the position's (a cancelled retry's).
  store.read([&](const StateStore::Data& data) {
    if (auto w = data.pending.find(d.name); w != data.pending.end()) {
      begun.drive_state = w->second.drive_state;
      begun.failures = w->second.failures;
      begun.failed_attempts = w->second.failed_attempts;
    } else if (auto st = data.states.find(d.name); st != data.states.end()) {
      begun.drive_state = st->second.drive_state;
    }
  });
  const std::string known = begun.drive_state;
  if (auto saved = store.save_pending(line, d, begun); !saved.ok())
    a.err = saved.error();
  else
    attempt_restore(a, job, li, f, audit, skip, cause, planned, plan_id);
  if (!a.err) a.err = ops::outcome_error(a.out);
  // Stopped by SIGTERM/SIGINT: the record stays, the next start finishes it;
  // the drive did not answer (busy resetting or saving when a killed service
  // left it) or its line could not be opened: the next run of the line tries
  // again (an automatic retry, a job of its own that an operator can cancel
  // while it waits).
  const bool interrupted = a.err && a.err->code == Errc::interrupted;
  const bool stays =
      interrupted || (a.err && (a.err->code == ErrorClass::link_failure || a.unopened));
  if (a.err) {
    // What reached the drive says what it holds: an attempt that wrote
    // nothing (the line did not open, the drive did not answer) leaves the
    // known state as it was.
    const std::size_t in_flight = jobs.read(job, [](const Job& j) { return j.step_done; });
    begun.drive_state =
        a.out.written || known.empty() ? words::drive_state_after(a.out, in_flight) : known;
    a.drive_state = begun.drive_state;
    jobs.update(job, [&](Job& j) { j.drive_state = begun.drive_state; });
    if (!job.retry_of.empty() && !interrupted)
      store.with([&](StateStore::Data& data) { note_retry_failed(job, *a.err, begun, data); });
  }
  if (!stays)
    store.remove_pending(line, d);
  else if (auto saved = store.save_pending(line, d, begun); !saved.ok())
    log("restore job " + job.id + ": " + saved.error().message);
  finish_restore_job(job, li, f, audit, cause, a, interrupted);
}

void Service::Impl::attempt_restore(RestoreAttempt& a, Job& job, std::size_t li,
                                    const fleet::ArchivedFile& f, const ops::Audit& audit,
                                    bool skip, const std::string& cause, const ops::Plan* planned,
                                    const std::string& plan_id) {
  using S = ops::RestoreOutcome::Stage;
  auto session = link::open_session(link_for(li, *f.drive));
  if (!session.ok()) {
    a.err = session.error();
    a.unopened = true;
    return;
  }
  a.out = ops::run_restore(**session, f.config, opt.db,
                           restore_run_options(job, li, *f.drive, skip, planned, plan_id));
  if (planned && a.out.stage != S::failed && !a.out.written) {
    if (auto e = plan_changed(*planned, a.out.plan, plan_id)) {
      a.out.stage = S::failed;
      a.out.error = *e;
    }
  }
  auto closed = (*session)->close();
  if (!closed.ok() && a.out.stage != S::failed) a.err = closed.error();
  if (a.out.written) {
    std::lock_guard<std::mutex> lock(archive_mu);
    auto made = archive.commit({}, fleet::restore_record_message(f, a.out, audit, cause), true);
    if (made.ok())
      a.record = *made;
    else
      a.err = made.error();
  }
  if (a.record) want_push();  // outside archive_mu: the pusher's lock is a leaf
}

ops::RestoreRunOptions Service::Impl::restore_run_options(Job& job, std::size_t li,
                                                          const fleet::DriveEntry& d, bool skip,
                                                          const ops::Plan* planned,
                                                          const std::string& plan_id) {
  const auto& line = opt.inventory.lines[li];
  ops::RestoreRunOptions ro;
  ro.restore = restore_options(line, d, skip);
  ro.restore.progress = [this, &job, planned](const std::string& phase, std::size_t done,
                                              std::size_t total) {
    jobs.update(job, [&](Job& j) {
      if (phase != "restore") {
        j.step = phase;
        return;
      }
      // Called as step `done` (1-based) begins.
      j.step_done = done > 0 ? done - 1 : 0;
      j.step_total = total;
      j.step = planned && done > 0 && done <= planned->steps.size()
                   ? planned->steps[done - 1].text
                   : "step " + std::to_string(done) + " of " + std::to_string(total);
    });
  };
  ro.undo = ops::UndoOptions{
      true, state_dir / "lmcfg" / "undo", line.port, d.id, "serve-restore", ops::kUndoKeep};
  if (planned) {
    ro.confirm = [planned, plan_id](const ops::Plan& now) -> Result<ops::Consent> {
      if (auto e = plan_changed(*planned, now, plan_id)) return *e;
      return ops::Consent::go;
    };
  }
  return ro;
}

void Service::Impl::finish_restore_job(Job& job, std::size_t li, const fleet::ArchivedFile& f,
                                       const ops::Audit& audit, const std::string& cause,
                                       const RestoreAttempt& a, bool interrupted) {
  using S = ops::RestoreOutcome::Stage;
  const auto& line = opt.inventory.lines[li];
  const auto& d = *f.drive;
  const auto& out = a.out;
  const auto& err = a.err;
  const std::string outcome =
      err ? (out.written ? "failed after writing" : "failed") : ops::outcome_name(out);
  const int code = err ? exit_code(*err) : (out.skipped_any() ? 7 : 0);
  std::string event;
  Json details{{"job", job.id},
               {"source", f.path + "@" + f.source.id.substr(0, 12)},
               {"outcome", outcome},
               {"automatic", !cause.empty()},
               {"operator", audit.who}};
  if (a.record) details["commit"] = a.record->id;
  const TimePoint now = opt.clock();
  jobs.update(job, [&](Job& j) {
    j.finished = now;
    j.failed_job = err.has_value();
    j.outcome = outcome;
    j.exit_code = code;
    // A failure leaves the steps done before it (a bar short of its end)
    // and the step it stopped in (the drive vanished during a flash save);
    // a read back that differs came after every step.
    if (!err || out.stage == S::verify_mismatch) {
      j.step_done = j.step_total;
      j.step = "";
    }
    j.message = err ? err->message
                    : (out.stage == S::nothing_to_do
                           ? "nothing to do: the drive already matches " + f.file_name
                           : "restored " + f.file_name + " onto " + d.name + " and verified");
    if (a.record) {
      j.commit = a.record->id;
      j.commits.push_back(a.record->id);
    }
    for (const auto& sv : out.plan.skipped_incompatible) j.skipped.push_back(sv.text);
    for (const auto& k : out.plan.kept) j.kept.push_back(ops::kept_json(k, "file"));
  });
  if (!interrupted) {
    store.with([&](StateStore::Data& data) {
      event = record_restore_state(data, d.name, a, code, f.file_name, details);
      if (!err) note_unapproved(data, d.name, f);
    });
  }
  log("restore job " + job.id + ": " + d.name + ": " + outcome +
      (err ? ": " + err->message : std::string()) +
      (a.record ? ", committed " + a.record->id.substr(0, 12) : std::string()));
  if (!interrupted) store.save();
  if (!event.empty()) emit(event, d.name, line.name, details);
}

// Caller holds store's lock. The position's state after a restore; the event
// to send, if any.
std::string Service::Impl::record_restore_state(StateStore::Data& data, const std::string& name,
                                                const RestoreAttempt& a, int code,
                                                const std::string& file_name, Json& details) {
  using S = ops::RestoreOutcome::Stage;
  std::string event;
  auto& st = data.states[name];
  st.last_attempt = opt.clock();
  st.last_kind = "restore";
  st.last_ok = !a.err;
  st.last_exit_code = code;
  const auto waiting = data.pending.find(name);
  st.drive_state.clear();
  if (a.err) {
    st.status = "failed";
    st.message = a.err->message;
    // What the drive holds, whether or not a retry waits.
    st.drive_state = waiting != data.pending.end() ? waiting->second.drive_state : a.drive_state;
    event = "restore_failed";
    details["reason"] = a.err->message;
    details["exit_code"] = code;
    if (waiting != data.pending.end()) details["retry"] = true;
    st.notified = "failed";
  } else if (a.out.skipped_any()) {
    // Not what the approved configuration holds: drift, with the values left
    // out, until they are approved or the drive changes.
    st.status = "drift";
    st.differing.clear();
    for (const auto& sv : a.out.plan.skipped_incompatible) st.differing.push_back(sv.text);
    st.differences = st.differing.size();
    st.message = "restored from " + file_name + " except " + std::to_string(st.differences) +
                 " value(s) this drive cannot take";
    if (a.out.written) event = "restored";
    st.notified = "drift";
  } else {
    st.status = "ok";
    st.message =
        a.out.stage == S::nothing_to_do ? "matches the archive" : "restored from " + file_name;
    // What the restore left as the drive holds it by policy: ok, and said.
    st.kept = Json::array();
    for (const auto& k : a.out.plan.kept) st.kept.push_back(ops::kept_json(k, "file"));
    st.differences = 0;
    st.differing.clear();
    if (a.out.written) event = "restored";
    st.notified = "ok";
  }
  return event;
}

// on_replaced = "restore": the approved configuration (HEAD when none), restored
// at once on this worker.
void Service::Impl::restore_replaced(std::size_t li, const fleet::DriveEntry& d) {
  if (lines.stopping()) return;
  auto job = jobs.add(Kind::restore, "drive " + d.name, d.name, [](Job& j) {
    j.who = kAutomatic;
    j.total = 1;
  });
  Result<fleet::ArchivedFile> f = [&] {
    std::lock_guard<std::mutex> lock(archive_mu);
    auto rev = restore_rev(d);
    if (!rev.ok()) return Result<fleet::ArchivedFile>(rev.error());
    auto file = fleet::load_archived(opt.inventory, archive, d.name, *rev);
    if (file.ok() && *rev != "HEAD") file->rev = "approved";
    return file;
  }();
  if (!f.ok()) {
    fail_job(*job, f.error());
    return;
  }
  run_restore_job(*job, li, *f, ops::Audit{kAutomatic, kReplacedCause, ""}, false,
                  "automatic: factory-fresh drive found", nullptr, "");
}

// Restores a previous run began and did not finish (killed, or stopped by a
// signal mid-restore): loaded at start and queued first on their lines.
void Service::Impl::queue_pending() {
  for (const std::string& name : store.load_pending(opt.inventory)) {
    const fleet::LineEntry* line = nullptr;
    opt.inventory.find_drive(name, &line);
    const std::size_t li = line_index(line);
    lines.push(li, Task{nullptr, {}, [this, li, name](bool run) {
                          if (run) resume(li, {name});
                        }});
  }
}

// Runs the unfinished restores of `names` again (on this line's worker): the
// same revision, who and why. Running a restore again converges
// (docs/restore.md); one stopped by a link failure (the drive was resetting
// or saving to flash when the service died) stays pending for the next run.
void Service::Impl::resume(std::size_t li, const std::vector<std::string>& names) {
  for (const auto& name : names) {
    const std::optional<PendingRestore> pr = store.pending(name);
    if (!pr || lines.stopping()) continue;
    auto job = jobs.add(Kind::restore, "drive " + name, name, [&](Job& j) {
      j.who = kRetry;
      j.asked_by = pr->who;
      j.retry_of = pr->origin_job;
      j.total = 1;
    });
    Result<fleet::ArchivedFile> f = [&] {
      std::lock_guard<std::mutex> lock(archive_mu);
      return fleet::load_archived(opt.inventory, archive, name, pr->commit);
    }();
    if (!f.ok()) {
      fail_job(*job,
               Error(f.error().code, "resuming the unfinished restore: " + f.error().message));
      continue;
    }
    log("restore job " + job->id + ": resuming the unfinished restore of " + name + " <- " +
        f->file_name);
    // The record names the retry in its subject; its Operator trailer stays the
    // person who asked for the restore.
    // An automatic restore resumed keeps its own cause.
    const std::string cause = pr->origin_job.empty() || !pr->cause.empty()
                                  ? pr->cause
                                  : "automatic retry of job " + pr->origin_job;
    run_restore_job(*job, li, *f, ops::Audit{pr->who, pr->reason, pr->ticket},
                    pr->skip_incompatible, cause, nullptr, "");
  }
}

Result<Json> Service::cancel_retry(const std::string& name, const std::string& who) {
  LMCFG_TRY(check_line("who", who, kMaxWhoBytes));
  auto& s = *impl_;
  const fleet::LineEntry* line = nullptr;
  const auto* d = s.opt.inventory.find_drive(name, &line);
  if (!d) return Error(Errc::not_found, "no drive named '" + name + "' in the inventory");
  const std::optional<PendingRestore> waiting = s.store.pending(name);
  if (!waiting) return Error(Errc::not_found, "no automatic retry is waiting for drive " + name);
  if (const std::string running = s.jobs.running_restore(name); !running.empty())
    return Error(Errc::plan_refused,
                 "the restore of drive " + name + " is running as job " + running +
                     ": it is not stopped between its writes; wait for it to end");
  const PendingRestore pr = *waiting;
  s.store.remove_pending(*line, *d);
  std::string state_words;
  s.store.with([&](StateStore::Data& data) {
    auto& st = data.states[name];
    st.drive_state = pr.drive_state;
    state_words = pr.drive_state.empty() ? "as the failed restore left it" : pr.drive_state;
    st.message = "automatic retry cancelled by " + (who.empty() ? "an operator" : who) +
                 "; the drive is " + state_words +
                 ": plan a restore to configure it, or check the drive";
  });
  s.store.save();
  s.log("automatic retry of the restore of " + name +
        (pr.origin_job.empty() ? "" : " (job " + pr.origin_job + ")") + " cancelled" +
        (who.empty() ? "" : " by " + who));
  s.emit("retry_cancelled", name, line->name,
         Json{{"job", pr.origin_job}, {"operator", who}, {"drive_state", pr.drive_state}});
  return Json{{"drive", name},
              {"cancelled_job", pr.origin_job.empty() ? Json(nullptr) : Json(pr.origin_job)},
              {"drive_state", pr.drive_state.empty() ? Json(nullptr) : Json(pr.drive_state)}};
}

// A plan for the API: the CLI's plan_json items (restore --dry-run --json),
// each step with its `kind` and the old and new values for people.
Json Service::Impl::plan_to_json(const StoredPlan& sp) const {
  const auto& line = opt.inventory.lines[sp.line];
  const auto& d = *sp.file.drive;
  const auto items = ops::plan_json(sp.plan);
  Json steps = Json::array();
  for (const auto& st : items["steps"]) {
    Json o;
    o["kind"] = st["action"];
    for (auto& [k, v] : st.items()) {
      if (k == "old" || k == "new") {
        o[k] = v.is_null() ? Json(nullptr) : Json(v["display"]);
        o[k + "_raw"] = v.is_null() ? Json(nullptr) : Json(v["raw"]);
      } else if (k != "action") {
        o[k] = v;
      }
    }
    if (st.contains("upid")) {
      const auto* p = opt.db.get().find(
          static_cast<std::uint16_t>(std::stoul(st["upid"].get<std::string>(), nullptr, 16)));
      o["unit"] = p ? p->spec.unit : "";
    }
    steps.push_back(std::move(o));
  }
  Json problems = Json::array();
  for (const auto& p : sp.plan.problems) problems.push_back({{"kind", "plan"}, {"message", p}});
  Json incompatible = Json::array();
  std::size_t n = 0;
  for (const auto& v : items["skipped_incompatible"]) {
    Json o = v;
    o["message"] = sp.plan.skipped_incompatible[n++].text;
    incompatible.push_back(std::move(o));
  }
  return Json{
      {"plan_id", sp.id},
      {"drive", d.name},
      {"line", line.name},
      {"id", hex(d.id, 2, "h")},
      {"rev", sp.file.rev},
      {"commit", sp.file.source.id},
      {"file", sp.file.file_name},
      {"who", sp.who},
      {"expires", iso_time(sp.expires)},
      {"nothing_to_do", sp.plan.nothing_to_do()},
      {"steps", steps},
      {"losses", items["losses"]},
      {"kept", items["kept"]},
      {"notes", items["notes"]},
      {"problems", problems},
      {"incompatible", incompatible},
      {"factory_fresh", factory_fresh(sp.plan.target, opt.db, fleet::ignored_upids(line, d))}};
}

}  // namespace lmcfg::serve
