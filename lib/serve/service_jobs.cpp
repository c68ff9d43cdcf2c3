// Backups and drift checks of the service (docs/serve.md), one worker per
// line: the line read, compared with the archive, committed (a backup), each
// position's state and events; the job's progress as GET /jobs/{id} shows it.
#include <algorithm>

#include "common/bytes.hpp"
#include "config/json_writer.hpp"
#include "ops/diff.hpp"
#include "serve/console.hpp"  // url_encode
#include "serve/service_impl.hpp"

namespace lmcfg::serve {

namespace detail {

namespace {

// Factory state as LinRS can see it: "With this functionality the whole
// parameter configuration of the servo controller could be read out" (LinRS
// §10.2): nothing modified means factory values. The MACID and baud rate a
// technician must set to put a new drive at the position (LinRS §3.2 "By
// Parameter", §10.2's example lists exactly those) and the position's ignored
// UPIDs do not count; no curve, no command table entry.
bool fresh_upid(std::uint16_t upid, const db::Database& db,
                const std::vector<std::uint16_t>& ignored) {
  return ops::is_comm_parameter(db, upid) ||
         std::find(ignored.begin(), ignored.end(), upid) != ignored.end();
}

}  // namespace

bool factory_fresh(const config::DriveConfig& cfg, const db::Database& db,
                   const std::vector<std::uint16_t>& ignored) {
  if (cfg.devicenet || !cfg.curves.empty() || !cfg.ct_entries.empty()) return false;
  for (const auto& layer : cfg.layers)
    for (const auto& p : layer)
      if (!fresh_upid(p.upid, db, ignored)) return false;
  return true;
}
// The same of what a restore plan read of the target.
bool factory_fresh(const ops::TargetSeen& t, const db::Database& db,
                   const std::vector<std::uint16_t>& ignored) {
  if ((t.ct_entries && !t.ct_entries->empty()) || (t.curves && !t.curves->empty())) return false;
  for (const auto& layer : t.layers)
    for (const auto& p : layer.value_or(std::vector<client::ModifiedParam>{}))
      if (!fresh_upid(p.upid, db, ignored)) return false;
  return true;
}

}  // namespace detail

// A factory-fresh drive where the archive holds a file: state `replaced`,
// the event once.
void Service::Impl::record_replaced(Kind kind, const fleet::DriveResult& r, bool restoring) {
  const bool send = store.with([&](StateStore::Data& data) {
    auto& st = data.states[r.name];
    st.last_attempt = opt.clock();
    st.last_kind = kind_name(kind);
    st.last_ok = true;
    st.last_exit_code = 0;
    st.status = "replaced";
    st.message = "a factory-fresh drive answers at this position; the archive holds its file";
    st.differences = r.diff.items.size();
    st.differing.clear();
    for (const auto& it : r.diff.items) st.differing.push_back(fleet::item_line(it));
    const bool changed = st.notified != "replaced";
    st.notified = "replaced";
    return changed;
  });
  if (send) {
    emit("replaced", r,
         {{"job", kind_name(kind)},
          {"differences", r.diff.items.size()},
          {"on_replaced", restoring ? "restore" : "notify"}});
  }
}

// One drive's outcome: its state, and an event when the state changed.
void Service::Impl::record(Kind kind, const fleet::DriveResult& r,
                           const std::optional<std::string>& commit) {
  const TimePoint now = opt.clock();
  std::string event;
  Json details;
  const std::string url = [&] {
    std::lock_guard<std::mutex> lock(mu);
    return base_url;
  }();
  store.with([&](StateStore::Data& data) {
    record_state(data.states[r.name], kind, r, commit, now, url, event, details);
  });
  if (!event.empty()) emit(event, r, details);
}

// Caller holds store's lock. One drive's outcome into its state `st`; the
// event to send (and its details) when the state changed.
void Service::Impl::record_state(DriveState& st, Kind kind, const fleet::DriveResult& r,
                                 const std::optional<std::string>& commit, TimePoint now,
                                 const std::string& url, std::string& event, Json& details) const {
  using S = fleet::DriveResult::Status;
  {
    st.last_attempt = now;
    st.last_kind = kind_name(kind);
    st.last_ok = r.status != S::failed;
    st.last_exit_code = r.error ? exit_code(*r.error) : 0;
    if (r.status == S::failed) {
      st.status = "failed";
      st.message = r.error ? r.error->message : "unknown error";
      if (st.notified != "failed") {
        event = "backup_failed";
        details = {
            {"job", kind_name(kind)}, {"reason", st.message}, {"exit_code", st.last_exit_code}};
        st.notified = "failed";
      }
    } else {
      if (kind == Kind::backup) st.last_backup = now;
      // Read whole: what it holds is what this read says (no restore waits on
      // it: those positions are not recorded here).
      st.drive_state.clear();
      st.kept = Json::array();
      for (const auto& k : r.kept) st.kept.push_back(ops::kept_json(k));
      st.differing.clear();
      for (const auto& it : r.diff.items) st.differing.push_back(fleet::item_line(it));
      st.differences = r.diff.items.size();
      if (r.status == S::changed) {
        // Against the approved configuration: a backup that archived the
        // change leaves the position in drift until someone approves the
        // change or restores the approved configuration.
        st.status = "drift";
        st.message = fleet::counts_line(r) + " differ from the approved configuration" +
                     (commit && kind == Kind::backup ? " (archived)" : "");
        if (st.notified != "drift") {
          event = "drift";
          st.notified = "drift";
        }
      } else if (r.status == S::added && kind == Kind::status) {
        st.status = "unknown";
        st.message = "not in the archive yet (no backup)";
      } else {
        const bool was_off =
            st.notified == "drift" || st.notified == "failed" || st.notified == "replaced";
        st.status = "ok";
        st.message = r.status == S::added ? "new, archived" : "matches the approved configuration";
        if (!r.kept.empty())
          st.message += "; " + std::to_string(r.kept.size()) +
                        " value(s) differ that the drive keeps by policy (listed as kept)";
        st.differences = 0;
        if (was_off) {
          event = "recovered";
          details = {{"job", kind_name(kind)}, {"previous", st.notified}};
        }
        st.notified = "ok";
      }
      if (event == "drift") {
        details = {{"job", kind_name(kind)},
                   {"parameters", r.count(ops::DiffItem::Kind::parameter)},
                   {"curves", r.count(ops::DiffItem::Kind::curve)},
                   {"ct_entries", r.count(ops::DiffItem::Kind::ct_entry)},
                   {"differences", r.diff.items.size()}};
        Json upids = Json::array();
        for (const auto& it : r.diff.items) {
          if (it.kind != ops::DiffItem::Kind::parameter) continue;
          upids.push_back({{"upid", hex(it.key, 4, "h")},
                           {"name", it.name},
                           {"archived", it.a},
                           {"live", it.b}});
        }
        details["upids"] = upids;
        if (commit && kind == Kind::backup) details["committed"] = *commit;
        // The diff rendered as lmcfg report does it: the archive against the
        // drive now, or (a backup committed it) the commit against its parent.
        const std::string from = st.approved ? st.approved->commit : std::string("HEAD");
        details["report"] = url + "/diff?name=" + url_encode(r.name) + "&from=" + from +
                            "&to=" + (commit && kind == Kind::backup ? *commit : "live");
      }
    }
  }
}

void Service::Impl::run_task(std::size_t line_index, Task& task) {
  const auto& line = opt.inventory.lines[line_index];
  auto& job = *task.job;
  fleet::FleetOptions fo;
  fo.db = opt.db;
  fo.backup = opt.backup;
  fo.on_drive = [this, &job](const fleet::DriveResult&, std::size_t, std::size_t) {
    jobs.update(job, [](Job& j) { ++j.done; });
  };
  resume_waiting(line_index, task.only);
  log(std::string(kind_name(job.kind)) + " job " + job.id + ": line " + line.name + " started");
  fleet::LineRun run = fleet::read_line(line, opt.links[line_index], fo, task.only);
  LineArchived la(run.drives.size());
  {
    std::lock_guard<std::mutex> lock(archive_mu);
    la.archived = archive_run(line, job, run, la);
  }
  std::vector<std::size_t> to_restore;
  const std::size_t failed = record_run(line, job.kind, run, la, to_restore);
  if (la.commit) want_push();
  count_run(line_index, job, run, la, failed);
  store.save();
  for (std::size_t i : to_restore) restore_replaced(line_index, *run.entries[i]);
}

// The restores a stopped service left unfinished on the drives in scope.
void Service::Impl::resume_waiting(std::size_t li, const std::vector<std::string>& only) {
  std::vector<std::string> waiting;
  for (const auto& d : opt.inventory.lines[li].drives) {
    const bool in_scope = only.empty() || std::find(only.begin(), only.end(), d.name) != only.end();
    if (in_scope && store.is_pending(d.name)) waiting.push_back(d.name);
  }
  resume(li, waiting);
}

// Caller holds archive_mu.
Result<void> Service::Impl::archive_run(const fleet::LineEntry& line, const Job& job,
                                        fleet::LineRun& run, LineArchived& la) {
  using S = fleet::DriveResult::Status;
  LMCFG_TRY(fleet::compare_line(line, archive, "HEAD", opt.db, run));
  LMCFG_ASSIGN_OR_RETURN(auto head, archive.resolve("HEAD"));
  const std::string before = head ? head->id : "";
  for (std::size_t i = 0; i < run.drives.size(); ++i) {
    // LinRS drives only: a DeviceNet capture has no modified lists (DeviceNet §5.2
    // values, read whole), so "factory-fresh" says nothing of it.
    la.replaced[i] =
        !line.devicenet && run.drives[i].status == S::changed && run.configs[i] &&
        factory_fresh(*run.configs[i], opt.db, fleet::ignored_upids(line, *run.entries[i]));
    // A drive a restore has not finished on is half configured: never archived.
    la.unfinished[i] = store.is_pending(run.entries[i]->name);
  }
  if (job.kind != Kind::backup) return compare_approved(line, job, before, run, la);
  // A replaced drive's factory state never overwrites the archived file.
  fleet::LineRun keep;
  for (std::size_t i = 0; i < run.drives.size(); ++i) {
    if (la.replaced[i] || la.unfinished[i]) continue;
    keep.entries.push_back(run.entries[i]);
    keep.drives.push_back(run.drives[i]);
    keep.configs.push_back(run.configs[i]);
  }
  LMCFG_ASSIGN_OR_RETURN(auto paths, fleet::write_line(archive, opt.db, keep));
  fleet::FleetRun fr;
  fr.drives = keep.drives;
  std::string message = fleet::commit_message(fr);
  const std::string tr = ops::trailers(ops::Audit{job.who, "", ""});
  if (!tr.empty()) message += "\n" + tr;
  LMCFG_ASSIGN_OR_RETURN(auto made, archive.commit(paths, message));
  if (made) la.commit = made->id;
  return compare_approved(line, job, before, run, la);
}

// Each drive's state and event; the drives to restore (replaced, on_replaced =
// "restore") into `to_restore`. Returns how many failed.
std::size_t Service::Impl::record_run(const fleet::LineEntry& line, Kind kind, fleet::LineRun& run,
                                      LineArchived& la, std::vector<std::size_t>& to_restore) {
  using S = fleet::DriveResult::Status;
  std::size_t failed = 0;
  for (std::size_t i = 0; i < run.drives.size(); ++i) {
    auto& r = run.drives[i];
    // A stop asked for mid-read is not the drive's failure: no state, no event.
    if (r.error && r.error->code == Errc::interrupted) continue;
    if (!la.archived.ok() && r.status != S::failed) {
      r.status = S::failed;
      r.error = la.archived.error();
      la.replaced[i] = false;
    }
    failed += r.status == S::failed;
    if (la.unfinished[i]) {
      // Its state is the restore's (failed, with the reason) until a restore finishes.
      continue;
    }
    if (la.replaced[i]) {
      const bool restore = fleet::restore_when_replaced(line, *run.entries[i]);
      record_replaced(kind, r, restore);
      if (restore) to_restore.push_back(i);
    } else {
      record(kind, la.archived.ok() && la.against[i] ? *la.against[i] : r, la.commit);
    }
  }
  return failed;
}

void Service::Impl::count_run(std::size_t li, Job& job, const fleet::LineRun& run,
                              const LineArchived& la, std::size_t failed) {
  const auto& line = opt.inventory.lines[li];
  LineMetrics m;
  m.telegrams = run.stats.requests;
  m.retries = run.stats.retries;
  m.timeouts = run.stats.timeouts;
  m.errors = failed;
  m.runs = 1;
  m.run_seconds = m.last_run_seconds = run.seconds;
  lines.count(li, m);
  const TimePoint now = opt.clock();
  jobs.update(job, [&](Job& j) { count_job(j, run, la, now); });
  char secs[32];
  std::snprintf(secs, sizeof secs, "%.1f", run.seconds);
  log(std::string(kind_name(job.kind)) + " job " + job.id + ": line " + line.name + " done in " +
      secs + " s: " + std::to_string(run.drives.size()) + " drive(s), " + std::to_string(failed) +
      " failed" + (la.commit ? ", committed " + la.commit->substr(0, 12) : std::string()));
}

// Caller holds jobs' lock. A line's run into its job's counts; the job ends
// with its last line.
void Service::Impl::count_job(Job& job, const fleet::LineRun& run, const LineArchived& la,
                              TimePoint now) {
  using S = fleet::DriveResult::Status;
  for (std::size_t i = 0; i < run.drives.size(); ++i) {
    const auto& r = run.drives[i];
    job.changed += r.status == S::changed && !la.replaced[i];
    job.replaced += la.replaced[i];
    job.unchanged += r.status == S::unchanged;
    job.added += r.status == S::added;
    job.failed += r.status == S::failed;
    if (r.error) job.errors.push_back(r.name + ": " + r.error->message);
  }
  if (la.commit) job.commits.push_back(*la.commit);
  if (--job.lines_left == 0) job.finished = now;
}

void Service::Impl::fail_job(Job& job, const Error& e, std::optional<int> code) {
  const TimePoint now = opt.clock();
  const int exit = code ? *code : exit_code(e);
  jobs.update(job, [&](Job& j) {
    j.started = true;
    j.finished = now;
    j.failed_job = true;
    j.outcome = "failed";
    j.message = e.message;
    j.exit_code = exit;
  });
  log(std::string(kind_name(job.kind)) + " job " + job.id + ": failed: " + e.message);
}

void Service::Impl::task_threw(std::size_t line, Task& task, const std::string& what) {
  const Error e = thrown_error(line, what);
  // 70: the CLI's exit code for a bug (README "Exit codes").
  if (task.job) fail_job(*task.job, e, 70);
}

bool Service::Impl::enqueue(std::size_t line, const std::shared_ptr<Job>& job,
                            std::vector<std::string> only) {
  const auto& l = opt.inventory.lines[line];
  jobs.update(*job, [&](Job& j) {
    j.total += only.empty() ? l.drives.size() : only.size();
    ++j.lines_left;
  });
  if (lines.push(line, Task{job, std::move(only), {}})) return true;
  stopped_before(*job);
  return false;
}

bool Service::Impl::enqueue_fn(std::size_t line, const std::shared_ptr<Job>& job,
                               std::function<void(bool run)> fn) {
  if (lines.push(line, Task{job, {}, std::move(fn)})) return true;
  if (job) stopped_before(*job);
  return false;
}

void Service::Impl::stopped_before(Job& job) {
  const TimePoint now = opt.clock();
  jobs.update(job, [&](Job& j) {
    if (j.finished) return;
    j.finished = now;
    j.failed_job = true;
    j.message = "the service stopped before the job ran";
  });
}

void Service::Impl::run_on_line(std::size_t line, Task& task) {
  if (task.job && !task.fn) jobs.update(*task.job, [](Job& j) { j.started = true; });
  // Nothing a job throws ends the process: the job fails and says why, the
  // line's next job runs.
  try {
    if (task.fn)
      task.fn(true);
    else
      run_task(line, task);
  } catch (const std::exception& e) {
    task_threw(line, task, e.what());
  } catch (...) {
    task_threw(line, task, "an exception of unknown type");
  }
}

// Waiting callers learn that nothing will run; queued jobs say so.
void Service::Impl::drop_tasks(std::deque<Task>& left) {
  for (auto& t : left)
    if (t.job) stopped_before(*t.job);
  for (auto& t : left)
    if (t.fn) t.fn(false);
}

template <class W>
void Service::Impl::write_drive(W& w, const fleet::LineEntry& line,
                                const fleet::DriveEntry& d) const {
  // Each part read in turn, under its own lock (none held together).
  const DriveState st = store.state(d.name);
  const std::optional<PendingRestore> pending = store.pending(d.name);
  w.begin_object();
  w.member("name", d.name);
  w.member("line", line.name);
  w.member("id", d.id);
  w.member("status", st.status);
  w.key("last_backup");
  if (st.last_backup)
    w.value(iso_time(*st.last_backup));
  else
    w.value(nullptr);
  w.key("last_attempt");
  if (st.last_attempt) {
    w.begin_object();
    w.member("time", iso_time(*st.last_attempt));
    w.member("job", st.last_kind);
    w.member("result", st.last_ok ? "ok" : "failed");
    w.member("exit_code", st.last_exit_code);
    w.end_object();
  } else {
    w.value(nullptr);
  }
  w.member("differences", static_cast<std::uint64_t>(st.differences));
  w.member("message", st.message);
  if (st.status == "drift") {
    w.key("differing");
    w.begin_array();
    for (const auto& line_text : st.differing) w.value(line_text);
    w.end_array();
  }
  w.member("kept", st.kept);
  w.key("approved");
  if constexpr (std::is_same_v<W, config::JsonTextWriter>)
    fleet::write_approval(w, st.approved);
  else
    w.value(fleet::approval_json(st.approved));
  w.member_or_null("drive_state", st.drive_state);
  // A failed restore the service will run again (before the line's next drift
  // check or backup) until an operator cancels it.
  w.key("retry");
  if (pending)
    write_retry(w, d.name, *pending);
  else
    w.value(nullptr);
  w.end_object();
}

// A restore waiting to run again, as a position shows it.
template <class W>
void Service::Impl::write_retry(W& w, const std::string& name, const PendingRestore& pr) const {
  const std::string running = jobs.running_restore(name);
  std::optional<TimePoint> next;
  {
    std::lock_guard<std::mutex> lock(mu);
    next = next_status;
    if (next_backup && (!next || *next_backup < *next)) next = next_backup;
  }
  w.begin_object();
  w.member_or_null("of_job", pr.origin_job);
  w.member("asked_by", pr.who);
  w.member("commit", pr.commit);
  w.member_or_null("drive_state", pr.drive_state);
  w.member("running", !running.empty());
  w.member("will",
           "restore the same revision again when the drive answers, before the line's next "
           "drift check or backup (a restore run again converges)");
  if (!running.empty()) {
    w.member("job", running);
  }
  // Each automatic retry that failed (the newest kept), and when the next runs.
  w.member("failed_attempts", static_cast<std::uint64_t>(pr.failed_attempts));
  w.key("failures");
  w.begin_array();
  for (const auto& f : pr.failures) {
    w.begin_object();
    w.member("time", f.time);
    w.member("job", f.job);
    w.member("reason", f.reason);
    w.end_object();
  }
  w.end_array();
  w.key("next_attempt");
  if (next)
    w.value(iso_time(*next));
  else
    w.value(nullptr);
  w.end_object();
}

Json Service::Impl::drive_json(const fleet::LineEntry& line, const fleet::DriveEntry& d) const {
  config::JsonBuilder b;
  write_drive(b, line, d);
  return b.take();
}

std::string Service::Impl::drives_text() const {
  std::string out;
  // About 560 bytes a position (a backed-up one, approved, no retry): one
  // allocation instead of the string's doublings at thousands of positions.
  out.reserve(opt.inventory.drive_count() * 600);
  config::JsonTextWriter w(out, 2);
  w.begin_array();
  for (const auto& line : opt.inventory.lines)
    for (const auto& d : line.drives) write_drive(w, line, d);
  w.end_array();
  return out;
}

}  // namespace lmcfg::serve
