#include "serve/service.hpp"

#include <algorithm>
#include <charconv>
#include <condition_variable>
#include <ctime>
#include <deque>
#include <future>
#include <map>
#include <mutex>
#include <random>
#include <thread>

#include "common/bytes.hpp"
#include "common/layers.hpp"
#include "config/atomic_file.hpp"
#include "config/config_io.hpp"
#include "fleet/archive.hpp"
#include "fleet/history.hpp"
#include "ops/diff.hpp"
#include "ops/recovery.hpp"
#include "ops/restore_run.hpp"
#include "ops/undo.hpp"
#include "report/report.hpp"
#include "serve/console.hpp"  // url_encode

namespace lmcfg::serve {

std::string iso_time(TimePoint t) {
  const std::time_t s = Clock::to_time_t(t);
  std::tm tm{};
  ::gmtime_r(&s, &tm);
  char buf[32];
  std::strftime(buf, sizeof buf, "%Y-%m-%dT%H:%M:%SZ", &tm);
  return buf;
}

namespace {

// Who an automatic restore records as its operator, and why.
constexpr const char* kAutomatic = "lmcfg serve (automatic)";
constexpr const char* kReplacedCause = "factory-fresh drive found at the position";

enum class Kind { backup, status, restore };
const char* kind_name(Kind k) {
  return k == Kind::backup ? "backup" : (k == Kind::status ? "status" : "restore");
}

double epoch_seconds(TimePoint t) {
  return std::chrono::duration<double>(t.time_since_epoch()).count();
}

struct Job {
  std::string id;
  Kind kind = Kind::backup;
  std::string scope;  // "drive NAME", "line NAME", "scheduled"
  TimePoint created;
  std::size_t total = 0, done = 0, lines_left = 0;
  std::size_t changed = 0, unchanged = 0, added = 0, failed = 0, replaced = 0;
  std::vector<std::string> commits, errors;
  bool started = false;  // a line's worker has taken it up
  std::optional<TimePoint> finished;
  std::string who;  // asked for by (API token's name, "local"); "" = scheduled
  // Restore jobs: the steps as they run, the outcome and its commit.
  bool failed_job = false;
  std::size_t step_done = 0, step_total = 0;
  std::string step, outcome, message, commit;
  std::optional<int> exit_code;
};

struct Task {
  std::shared_ptr<Job> job;
  std::vector<std::string> only;  // drive names; empty = the whole line
  // Work other than a backup or drift check (plans, restores, live reads), run
  // on the line's worker: fn(true); fn(false) when the service stops first.
  std::function<void(bool run)> fn;
};

// A plan made for the API: what execute() needs, kept until it expires.
struct StoredPlan {
  std::string id;
  fleet::ArchivedFile file;
  std::size_t line = 0;
  ops::Plan plan;
  std::string who;
  TimePoint expires;
};

// A restore the service began and has not finished: written before the
// first write, removed after the outcome is recorded; a start that finds one
// (the service was killed mid-restore) runs the restore again, which converges.
struct PendingRestore {
  std::string drive, commit, who, reason, ticket, cause;
  bool skip_incompatible = false;
};

// "press3/z" and MACID 11h on line "line1": "line1-11h.json" (names are
// archive paths, so '/' cannot be in a file name; a line's MACIDs are unique).
std::string pending_name(const fleet::LineEntry& line, const fleet::DriveEntry& d) {
  std::string n = line.name + "-" + hex(d.id, 2, "h") + ".json";
  for (char& c : n)
    if (c == '/') c = '_';
  return n;
}

std::string random_id() {
  std::random_device rd;
  std::string id;
  for (int i = 0; i < 4; ++i) id += hex(rd(), 8, "");
  for (char& c : id) c = static_cast<char>(std::tolower(static_cast<unsigned char>(c)));
  return id;
}

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

// What the service knows about one position.
struct DriveState {
  std::string status = "unknown";  // ok, drift, failed, replaced, unknown
  std::string message = "not read yet";
  std::optional<TimePoint> last_backup;
  std::optional<TimePoint> last_attempt;
  std::string last_kind;
  bool last_ok = false;
  int last_exit_code = 0;
  std::size_t differences = 0;
  std::vector<std::string> differing;  // the differences, as the commit message says them
  std::string notified;                // the last state an event was sent for
};

struct LineMetrics {
  std::uint64_t telegrams = 0, retries = 0, timeouts = 0, errors = 0, runs = 0;
  double run_seconds = 0, last_run_seconds = 0;
};

// Prometheus label value: backslash, double quote and newline escaped.
std::string label(std::string_view v) {
  std::string s;
  for (char c : v) {
    if (c == '\\' || c == '"') s += '\\';
    if (c == '\n') {
      s += "\\n";
      continue;
    }
    s += c;
  }
  return s;
}

std::string number(double v) {
  char buf[40];
  std::snprintf(buf, sizeof buf, "%.17g", v);
  return buf;
}

}  // namespace

struct Service::Impl {
  ServiceOptions opt;
  fleet::Archive archive;
  TimePoint started;
  std::optional<TimePoint> next_backup, next_status;

  mutable std::mutex mu;  // states, metrics, jobs, queues
  std::condition_variable cv;
  std::map<std::string, DriveState> states;  // by position name
  std::vector<LineMetrics> line_metrics;
  std::map<std::uint64_t, std::shared_ptr<Job>> jobs;  // by number: begin() is the oldest
  std::uint64_t next_job = 1;
  std::vector<std::deque<Task>> queues;  // one per line
  std::vector<bool> busy;
  bool stopping = false;
  std::vector<std::thread> workers;

  std::mutex archive_mu;  // libgit2's repository: one user at a time
  std::string base_url;   // under mu: set_base_url

  // [archive] push, under mu. A commit asks for a push (++wanted); the push
  // thread pushes the branch as it then is and marks that request done, so
  // commits made during a push are pushed by the next one.
  struct PushState {
    std::uint64_t wanted = 0, done = 0, failures = 0;
    std::optional<TimePoint> last_success;
    bool failing = false;  // in a failure episode (push_failed sent, no success since)
  } push;
  std::condition_variable push_cv;
  std::thread pusher;
  std::map<std::string, StoredPlan> plans;  // by id (under mu)
  // Restores begun and not finished, by position (under mu; on disk in pending/).
  std::map<std::string, PendingRestore> pending;
  // pending/ (restores begun), lmcfg/ (recovery and undo records, laid out as
  // $XDG_STATE_HOME/lmcfg is for the CLI: XDG_STATE_HOME=<state_dir> lmcfg undo --list)
  std::filesystem::path state_dir;
  std::optional<std::int64_t> summary_day;  // days since the epoch of the last summary

  Impl(ServiceOptions o, fleet::Archive a) : opt(std::move(o)), archive(std::move(a)) {}

  std::size_t line_index(const fleet::LineEntry* l) const {
    return static_cast<std::size_t>(l - opt.inventory.lines.data());
  }
  link::LinkSpec link_for(std::size_t line, const fleet::DriveEntry& d) const {
    return opt.links[line].linrs.for_macid(d.id);
  }

  // Runs `fn` on the line's worker (after what is queued there) and waits for it.
  template <class T>
  Result<T> on_worker(std::size_t line, std::function<Result<T>()> fn) {
    auto promise = std::make_shared<std::promise<Result<T>>>();
    auto future = promise->get_future();
    {
      std::lock_guard<std::mutex> lock(mu);
      if (stopping) return Error(Errc::interrupted, "the service is stopping");
      queues[line].push_back(Task{nullptr, {}, [promise, fn](bool run) {
                                    if (run)
                                      promise->set_value(fn());
                                    else
                                      promise->set_value(
                                          Error(Errc::interrupted, "the service is stopping"));
                                  }});
      cv.notify_all();
    }
    return future.get();
  }

  // The restore options of a position: its recovery record in the state directory.
  ops::RestoreOptions restore_options(const fleet::LineEntry& line, const fleet::DriveEntry& d,
                                      bool skip_incompatible) const {
    ops::RestoreOptions ro;
    ro.port = line.port;
    ro.recovery_path =
        state_dir / "lmcfg" / ("restore-" + ops::drive_key(line.port, d.id) + ".json");
    ro.skip_incompatible = skip_incompatible;
    return ro;
  }

  Result<void> save_pending(const fleet::LineEntry& line, const fleet::DriveEntry& d,
                            const PendingRestore& p) {
    const Json j{{"drive", p.drive},
                 {"commit", p.commit},
                 {"who", p.who},
                 {"reason", p.reason},
                 {"ticket", p.ticket},
                 {"cause", p.cause},
                 {"skip_incompatible", p.skip_incompatible}};
    std::error_code ec;
    std::filesystem::create_directories(state_dir / "pending", ec);
    LMCFG_TRY(
        config::write_file_atomic(state_dir / "pending" / pending_name(line, d), j.dump() + "\n"));
    std::lock_guard<std::mutex> lock(mu);
    pending[d.name] = p;
    return {};
  }
  void remove_pending(const fleet::LineEntry& line, const fleet::DriveEntry& d) {
    std::error_code ec;
    std::filesystem::remove(state_dir / "pending" / pending_name(line, d), ec);
    std::lock_guard<std::mutex> lock(mu);
    pending.erase(d.name);
  }
  bool is_pending(const std::string& name) const {
    std::lock_guard<std::mutex> lock(mu);
    return pending.count(name) != 0;
  }

  void log(const std::string& s) const {
    if (opt.log) opt.log(s);
  }
  int exit_code(const Error& e) const { return opt.exit_code ? opt.exit_code(e) : 70; }

  std::shared_ptr<Job> new_job(Kind kind, std::string scope) {
    auto j = std::make_shared<Job>();
    const std::uint64_t number = next_job++;
    j->id = std::to_string(number);
    j->kind = kind;
    j->scope = std::move(scope);
    j->created = opt.clock();
    jobs[number] = j;
    // The newest 1000 jobs are kept for GET /jobs/{id}.
    while (jobs.size() > 1000) jobs.erase(jobs.begin());
    return j;
  }

  // Caller holds mu.
  void enqueue(std::size_t line, std::shared_ptr<Job> job, std::vector<std::string> only) {
    const auto& l = opt.inventory.lines[line];
    job->total += only.empty() ? l.drives.size() : only.size();
    ++job->lines_left;
    queues[line].push_back(Task{std::move(job), std::move(only), {}});
    cv.notify_all();
  }

  // A commit was made: with [archive] push, the push thread pushes it.
  void want_push() {
    if (opt.inventory.archive.push.empty()) return;
    std::lock_guard<std::mutex> lock(mu);
    ++push.wanted;
    push_cv.notify_all();
  }

  // An event about the archive, not a position: push_failed, push_recovered.
  void emit_archive(const std::string& event, Json details) {
    Json j{
        {"event", event}, {"remote", opt.inventory.archive.push}, {"time", iso_time(opt.clock())}};
    for (auto& [k, v] : details.items()) j[k] = v;
    log("event " + event + ": push to " + opt.inventory.archive.push);
    if (opt.notify) opt.notify(j);
  }

  // The push thread. Its own handle on the repository: a slow or unreachable
  // remote holds neither archive_mu nor a line's worker, so backups and
  // commits go on and only the push waits.
  void push_loop() {
    const std::string& remote = opt.inventory.archive.push;
    auto repo = fleet::Archive::open(opt.archive, false);
    std::chrono::milliseconds wait = opt.push_retry_first;
    std::unique_lock<std::mutex> lock(mu);
    for (;;) {
      push_cv.wait(lock, [&] { return stopping || push.wanted > push.done; });
      if (stopping) return;
      const std::uint64_t asked = push.wanted;
      lock.unlock();
      Result<void> pushed = repo.ok() ? repo->push(remote) : Result<void>(repo.error());
      lock.lock();
      if (pushed.ok()) {
        push.done = std::max(push.done, asked);
        push.last_success = opt.clock();
        wait = opt.push_retry_first;
        const bool recovered = std::exchange(push.failing, false);
        lock.unlock();
        log("pushed the archive to " + remote);
        if (recovered) emit_archive("push_recovered", {});
        lock.lock();
        continue;
      }
      ++push.failures;
      const bool first = !std::exchange(push.failing, true);
      lock.unlock();
      log("push to " + remote + " failed, next try in " + std::to_string(wait.count()) +
          " ms: " + pushed.error().message);
      if (first) emit_archive("push_failed", {{"reason", pushed.error().message}});
      lock.lock();
      push_cv.wait_for(lock, wait, [&] { return stopping; });
      wait = std::min(wait * 2, opt.push_retry_max);
    }
  }

  void emit(const std::string& event, const std::string& drive, const std::string& line,
            Json details) {
    Json j{{"event", event},
           {"drive", drive.empty() ? Json(nullptr) : Json(drive)},
           {"line", line.empty() ? Json(nullptr) : Json(line)},
           {"time", iso_time(opt.clock())}};
    for (auto& [k, v] : details.items()) j[k] = v;
    log("event " + event + (drive.empty() ? "" : ": " + drive + " (line " + line + ")"));
    if (opt.notify) opt.notify(j);
  }
  void emit(const std::string& event, const fleet::DriveResult& r, Json details) {
    emit(event, r.name, r.line, std::move(details));
  }

  // A factory-fresh drive where the archive holds a file: state `replaced`,
  // the event once.
  void record_replaced(Kind kind, const fleet::DriveResult& r, bool restoring) {
    bool send = false;
    {
      std::lock_guard<std::mutex> lock(mu);
      auto& st = states[r.name];
      st.last_attempt = opt.clock();
      st.last_kind = kind_name(kind);
      st.last_ok = true;
      st.last_exit_code = 0;
      st.status = "replaced";
      st.message = "a factory-fresh drive answers at this position; the archive holds its file";
      st.differences = r.diff.items.size();
      st.differing.clear();
      for (const auto& it : r.diff.items) st.differing.push_back(fleet::item_line(it));
      send = st.notified != "replaced";
      st.notified = "replaced";
    }
    if (send) {
      emit("replaced", r,
           {{"job", kind_name(kind)},
            {"differences", r.diff.items.size()},
            {"on_replaced", restoring ? "restore" : "notify"}});
    }
  }

  // Runs a restore of `f` on this line's worker thread (the caller is it):
  // the normal restore (plan against the target, undo record, execute,
  // verify), recorded as a commit with the audit trailers. `planned`: the plan
  // the API showed; the target must still read as it found it.
  void run_restore_job(Job& job, std::size_t li, const fleet::ArchivedFile& f,
                       const ops::Audit& audit, bool skip, const std::string& cause,
                       const ops::Plan* planned, const std::string& plan_id) {
    using S = ops::RestoreOutcome::Stage;
    const auto& line = opt.inventory.lines[li];
    const auto& d = *f.drive;
    {
      std::lock_guard<std::mutex> lock(mu);
      job.started = true;
      if (planned) job.step_total = planned->steps.size();
    }
    log("restore job " + job.id + ": " + d.name + " <- " + f.file_name + " started" +
        (audit.who.empty() ? "" : " for " + audit.who));
    ops::RestoreOutcome out;
    std::optional<Error> err;
    std::optional<fleet::CommitInfo> record;
    const PendingRestore begun{d.name,       f.source.id, audit.who, audit.reason,
                               audit.ticket, cause,       skip};
    if (auto saved = save_pending(line, d, begun); !saved.ok()) {
      err = saved.error();
    } else if (auto session = link::open_session(link_for(li, d)); !session.ok()) {
      err = session.error();
    } else {
      ops::RestoreRunOptions ro;
      ro.restore = restore_options(line, d, skip);
      ro.restore.progress = [this, &job, planned](const std::string& phase, std::size_t done,
                                                  std::size_t total) {
        std::lock_guard<std::mutex> lock(mu);
        if (phase != "restore") {
          job.step = phase;
          return;
        }
        // Called as step `done` (1-based) begins.
        job.step_done = done > 0 ? done - 1 : 0;
        job.step_total = total;
        job.step = planned && done > 0 && done <= planned->steps.size()
                       ? planned->steps[done - 1].text
                       : "step " + std::to_string(done) + " of " + std::to_string(total);
      };
      ro.undo = ops::UndoOptions{
          true, state_dir / "lmcfg" / "undo", line.port, d.id, "serve-restore", ops::kUndoKeep};
      auto changed = [&](const ops::Plan& now) -> std::optional<Error> {
        const std::string what = ops::target_change(*planned, now);
        if (what.empty()) return std::nullopt;
        return Error(Errc::plan_refused, "the target changed since plan " + plan_id +
                                             " was made (" + what +
                                             "); nothing written: make a new plan");
      };
      if (planned) {
        ro.confirm = [&](const ops::Plan& now) -> Result<ops::Consent> {
          if (auto e = changed(now)) return *e;
          return ops::Consent::go;
        };
      }
      out = ops::run_restore(**session, f.config, opt.db, ro);
      if (planned && out.stage != S::failed && !out.written) {
        if (auto e = changed(out.plan)) {
          out.stage = S::failed;
          out.error = *e;
        }
      }
      auto closed = (*session)->close();
      if (!closed.ok() && out.stage != S::failed) err = closed.error();
      if (out.written) {
        std::lock_guard<std::mutex> lock(archive_mu);
        auto made = archive.commit({}, fleet::restore_record_message(f, out, audit, cause), true);
        if (made.ok())
          record = *made;
        else
          err = made.error();
      }
      if (record) want_push();  // outside archive_mu: want_push takes mu
    }
    if (!err && out.stage == S::failed && out.error) err = out.error;
    if (!err && out.stage == S::plan_refused) {
      std::string all;
      for (const auto& p : out.plan.problems) all += (all.empty() ? "" : "; ") + p;
      err = Error(Errc::plan_refused, "restore refused: " + all + "; nothing written");
    }
    if (!err && out.stage == S::verify_mismatch) {
      std::string all;
      for (const auto& m : out.mismatches) all += (all.empty() ? "" : "; ") + m;
      err = Error(Errc::verify_mismatch, "written, but the drive reads back differently: " + all);
    }
    // Stopped by SIGTERM/SIGINT: the record stays, the next start finishes it;
    // the drive did not answer (busy resetting or saving when a killed service
    // left it): the next run of the line tries again.
    const bool interrupted = err && err->code == Errc::interrupted;
    const bool stays = interrupted || (err && err->code == ErrorClass::link_failure);
    if (!stays) remove_pending(line, d);

    const std::string outcome =
        err ? (out.written ? "failed after writing" : "failed") : ops::outcome_name(out);
    const int code = err ? exit_code(*err) : (out.skipped_any() ? 7 : 0);
    std::string event;
    Json details{{"job", job.id},
                 {"source", f.path + "@" + f.source.id.substr(0, 12)},
                 {"outcome", outcome},
                 {"automatic", !cause.empty()},
                 {"operator", audit.who}};
    if (record) details["commit"] = record->id;
    {
      std::lock_guard<std::mutex> lock(mu);
      job.finished = opt.clock();
      job.failed_job = err.has_value();
      job.outcome = outcome;
      job.exit_code = code;
      if (out.stage != S::failed || out.written) job.step_done = job.step_total;
      job.step = "";
      job.message = err ? err->message
                        : (out.stage == S::nothing_to_do
                               ? "nothing to do: the drive already matches " + f.file_name
                               : "restored " + f.file_name + " onto " + d.name + " and verified");
      if (record) {
        job.commit = record->id;
        job.commits.push_back(record->id);
      }
      if (!interrupted) {
        auto& st = states[d.name];
        st.last_attempt = opt.clock();
        st.last_kind = "restore";
        st.last_ok = !err;
        st.last_exit_code = code;
        if (err) {
          st.status = "failed";
          st.message = err->message;
          event = "restore_failed";
          details["reason"] = err->message;
          details["exit_code"] = code;
          st.notified = "failed";
        } else {
          st.status = "ok";
          st.message = out.stage == S::nothing_to_do ? "matches the archive"
                                                     : "restored from " + f.file_name;
          st.differences = 0;
          st.differing.clear();
          if (out.written) event = "restored";
          st.notified = "ok";
        }
      }
    }
    log("restore job " + job.id + ": " + d.name + ": " + outcome +
        (err ? ": " + err->message : std::string()) +
        (record ? ", committed " + record->id.substr(0, 12) : std::string()));
    if (!event.empty()) emit(event, d.name, line.name, details);
  }

  // One drive's outcome: its state, and an event when the state changed.
  void record(Kind kind, const fleet::DriveResult& r, const std::optional<std::string>& commit) {
    using S = fleet::DriveResult::Status;
    const TimePoint now = opt.clock();
    std::string event;
    Json details;
    {
      std::lock_guard<std::mutex> lock(mu);
      auto& st = states[r.name];
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
        st.differing.clear();
        for (const auto& it : r.diff.items) st.differing.push_back(fleet::item_line(it));
        st.differences = r.diff.items.size();
        if (r.status == S::changed && kind == Kind::status) {
          st.status = "drift";
          st.message = fleet::counts_line(r) + " differ from the archive";
          if (st.notified != "drift") {
            event = "drift";
            st.notified = "drift";
          }
        } else if (r.status == S::changed) {
          // A backup archives what it found: the position matches the archive
          // again, and the event says the change was committed.
          st.status = "ok";
          st.message = "changed, archived";
          event = "drift";
          st.notified = "ok";
          st.differences = 0;
        } else if (r.status == S::added && kind == Kind::status) {
          st.status = "unknown";
          st.message = "not in the archive yet (no backup)";
        } else {
          const bool was_off =
              st.notified == "drift" || st.notified == "failed" || st.notified == "replaced";
          st.status = "ok";
          st.message = r.status == S::added ? "new, archived" : "matches the archive";
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
          if (commit) details["committed"] = *commit;
          // The diff rendered as lmcfg report does it: the archive against the
          // drive now, or (a backup committed it) the commit against its parent.
          details["report"] = base_url + "/diff?name=" + url_encode(r.name) +
                              (commit ? "&from=" + *commit + "~1&to=" + *commit
                                      : std::string("&from=HEAD&to=live"));
        }
      }
    }
    if (!event.empty()) emit(event, r, details);
  }

  void run_task(std::size_t line_index, Task& task) {
    const auto& line = opt.inventory.lines[line_index];
    auto& job = *task.job;
    fleet::FleetOptions fo;
    fo.db = opt.db;
    fo.backup = opt.backup;
    fo.on_drive = [this, &job](const fleet::DriveResult&, std::size_t, std::size_t) {
      std::lock_guard<std::mutex> lock(mu);
      ++job.done;
    };
    {
      std::vector<std::string> waiting;
      for (const auto& d : line.drives) {
        const bool in_scope = task.only.empty() || std::find(task.only.begin(), task.only.end(),
                                                             d.name) != task.only.end();
        if (in_scope && is_pending(d.name)) waiting.push_back(d.name);
      }
      resume(line_index, waiting);
    }
    log(std::string(kind_name(job.kind)) + " job " + job.id + ": line " + line.name + " started");
    fleet::LineRun run = fleet::read_line(line, opt.links[line_index], fo, task.only);
    using S = fleet::DriveResult::Status;
    std::optional<std::string> commit;
    Result<void> archived;
    std::vector<bool> replaced(run.drives.size(), false), unfinished(run.drives.size(), false);
    {
      std::lock_guard<std::mutex> lock(archive_mu);
      archived = [&]() -> Result<void> {
        LMCFG_TRY(fleet::compare_line(line, archive, "HEAD", opt.db, run));
        for (std::size_t i = 0; i < run.drives.size(); ++i) {
          // LinRS drives only: a DeviceNet capture has no modified lists (DeviceNet §5.2
          // values, read whole), so "factory-fresh" says nothing of it.
          replaced[i] =
              !line.devicenet && run.drives[i].status == S::changed && run.configs[i] &&
              factory_fresh(*run.configs[i], opt.db, fleet::ignored_upids(line, *run.entries[i]));
          // A drive a restore has not finished on is half configured: never archived.
          unfinished[i] = is_pending(run.entries[i]->name);
        }
        if (job.kind != Kind::backup) return {};
        // A replaced drive's factory state never overwrites the archived file.
        fleet::LineRun keep;
        for (std::size_t i = 0; i < run.drives.size(); ++i) {
          if (replaced[i] || unfinished[i]) continue;
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
        if (made) commit = made->id;
        return {};
      }();
    }
    std::size_t failed = 0;
    std::vector<std::size_t> to_restore;
    for (std::size_t i = 0; i < run.drives.size(); ++i) {
      auto& r = run.drives[i];
      // A stop asked for mid-read is not the drive's failure: no state, no event.
      if (r.error && r.error->code == Errc::interrupted) continue;
      if (!archived.ok() && r.status != S::failed) {
        r.status = S::failed;
        r.error = archived.error();
        replaced[i] = false;
      }
      failed += r.status == S::failed;
      if (unfinished[i]) {
        // Its state is the restore's (failed, with the reason) until a restore finishes.
        continue;
      }
      if (replaced[i]) {
        const bool restore = fleet::restore_when_replaced(line, *run.entries[i]);
        record_replaced(job.kind, r, restore);
        if (restore) to_restore.push_back(i);
      } else {
        record(job.kind, r, commit);
      }
    }
    if (commit) want_push();
    std::unique_lock<std::mutex> lock(mu);
    auto& m = line_metrics[line_index];
    m.telegrams += run.stats.requests;
    m.retries += run.stats.retries;
    m.timeouts += run.stats.timeouts;
    m.errors += failed;
    ++m.runs;
    m.run_seconds += run.seconds;
    m.last_run_seconds = run.seconds;
    for (const auto& r : run.drives) {
      job.changed += r.status == S::changed && !replaced[&r - run.drives.data()];
      job.replaced += replaced[&r - run.drives.data()];
      job.unchanged += r.status == S::unchanged;
      job.added += r.status == S::added;
      job.failed += r.status == S::failed;
      if (r.error) job.errors.push_back(r.name + ": " + r.error->message);
    }
    if (commit) job.commits.push_back(*commit);
    if (--job.lines_left == 0) job.finished = opt.clock();
    char secs[32];
    std::snprintf(secs, sizeof secs, "%.1f", run.seconds);
    log(std::string(kind_name(job.kind)) + " job " + job.id + ": line " + line.name + " done in " +
        secs + " s: " + std::to_string(run.drives.size()) + " drive(s), " + std::to_string(failed) +
        " failed" + (commit ? ", committed " + commit->substr(0, 12) : std::string()));
    lock.unlock();
    for (std::size_t i : to_restore) restore_replaced(line_index, *run.entries[i]);
  }

  // on_replaced = "restore": the archived file at HEAD, restored at once on this worker.
  void restore_replaced(std::size_t li, const fleet::DriveEntry& d) {
    std::shared_ptr<Job> job;
    {
      std::lock_guard<std::mutex> lock(mu);
      if (stopping) return;
      job = new_job(Kind::restore, "drive " + d.name);
      job->who = kAutomatic;
      job->total = 1;
    }
    Result<fleet::ArchivedFile> f = [&] {
      std::lock_guard<std::mutex> lock(archive_mu);
      return fleet::load_archived(opt.inventory, archive, d.name, "HEAD");
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
  void load_pending() {
    std::error_code ec;
    for (const auto& entry : std::filesystem::directory_iterator(state_dir / "pending", ec)) {
      const auto path = entry.path();
      if (path.extension() != ".json") continue;
      auto text = config::read_text_file(path, 1 << 16);
      Json j = text.ok() ? Json::parse(*text, nullptr, false) : Json();
      const fleet::LineEntry* line = nullptr;
      const fleet::DriveEntry* d =
          j.is_object() && j["drive"].is_string()
              ? opt.inventory.find_drive(j["drive"].get<std::string>(), &line)
              : nullptr;
      if (!d) {
        log("unfinished restore record " + path.string() +
            " names no drive of the inventory; left as it is");
        continue;
      }
      pending[d->name] = PendingRestore{j.value("drive", ""),
                                        j.value("commit", ""),
                                        j.value("who", ""),
                                        j.value("reason", ""),
                                        j.value("ticket", ""),
                                        j.value("cause", ""),
                                        j.value("skip_incompatible", false)};
      const std::size_t li = line_index(line);
      const std::string name = d->name;
      queues[li].push_back(Task{nullptr, {}, [this, li, name](bool run) {
                                  if (run) resume(li, {name});
                                }});
    }
  }

  // Runs the unfinished restores of `names` again (on this line's worker): the
  // same revision, who and why. Running a restore again converges
  // (docs/restore.md); one stopped by a link failure (the drive was resetting
  // or saving to flash when the service died) stays pending for the next run.
  void resume(std::size_t li, const std::vector<std::string>& names) {
    for (const auto& name : names) {
      std::optional<PendingRestore> pr;
      std::shared_ptr<Job> job;
      {
        std::lock_guard<std::mutex> lock(mu);
        auto it = pending.find(name);
        if (it == pending.end() || stopping) continue;
        pr = it->second;
        job = new_job(Kind::restore, "drive " + name);
        job->who = pr->who;
        job->total = 1;
      }
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
      run_restore_job(*job, li, *f, ops::Audit{pr->who, pr->reason, pr->ticket},
                      pr->skip_incompatible, pr->cause, nullptr, "");
    }
  }

  void fail_job(Job& job, const Error& e) {
    std::lock_guard<std::mutex> lock(mu);
    job.started = true;
    job.finished = opt.clock();
    job.failed_job = true;
    job.outcome = "failed";
    job.message = e.message;
    job.exit_code = exit_code(e);
    log(std::string(kind_name(job.kind)) + " job " + job.id + ": failed: " + e.message);
  }

  void worker(std::size_t line) {
    std::unique_lock<std::mutex> lock(mu);
    for (;;) {
      cv.wait(lock, [&] { return stopping || !queues[line].empty(); });
      if (stopping) {
        // Waiting callers learn that nothing will run; queued jobs say so.
        std::deque<Task> left = std::move(queues[line]);
        queues[line].clear();
        for (auto& t : left) {
          if (t.job && !t.job->finished) {
            t.job->finished = opt.clock();
            t.job->failed_job = true;
            t.job->message = "the service stopped before the job ran";
          }
        }
        lock.unlock();
        for (auto& t : left)
          if (t.fn) t.fn(false);
        return;
      }
      Task task = std::move(queues[line].front());
      queues[line].pop_front();
      busy[line] = true;
      if (task.job && !task.fn) task.job->started = true;
      lock.unlock();
      if (task.fn)
        task.fn(true);
      else
        run_task(line, task);
      lock.lock();
      busy[line] = false;
      cv.notify_all();
    }
  }

  Json job_json(const Job& j) const {
    const char* state =
        j.finished ? (j.failed_job ? "failed" : "done") : (j.started ? "running" : "queued");
    Json out{{"id", j.id},
             {"kind", kind_name(j.kind)},
             {"scope", j.scope},
             {"state", state},
             {"created", iso_time(j.created)},
             {"finished", j.finished ? Json(iso_time(*j.finished)) : Json(nullptr)},
             {"who", j.who.empty() ? Json(nullptr) : Json(j.who)}};
    if (j.kind == Kind::restore) {
      out["progress"] = {{"done", j.step_done}, {"total", j.step_total}, {"step", j.step}};
      out["outcome"] = j.outcome.empty() ? Json(nullptr) : Json(j.outcome);
      out["message"] = j.message;
      out["exit_code"] = j.exit_code ? Json(*j.exit_code) : Json(nullptr);
      out["commit"] = j.commit.empty() ? Json(nullptr) : Json(j.commit);
      return out;
    }
    out["progress"] = {{"done", j.done}, {"total", j.total}, {"step", ""}};
    out["outcome"] = j.finished ? Json(j.failed ? "some drives failed" : "done") : Json(nullptr);
    out["message"] = j.message;
    out["commit"] = j.commits.empty() ? Json(nullptr) : Json(j.commits.back());
    out["drives"] = j.total;
    out["done"] = j.done;
    out["counts"] = {{"unchanged", j.unchanged},
                     {"changed", j.changed},
                     {"new", j.added},
                     {"failed", j.failed},
                     {"replaced", j.replaced}};
    out["commits"] = j.commits;
    out["errors"] = j.errors;
    return out;
  }

  // A plan for the API: the CLI's plan_json items (restore --dry-run --json),
  // each step with its `kind` and the old and new values for people.
  Json plan_to_json(const StoredPlan& sp) const {
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
        {"notes", items["notes"]},
        {"problems", problems},
        {"incompatible", incompatible},
        {"factory_fresh", factory_fresh(sp.plan.target, opt.db, fleet::ignored_upids(line, d))}};
  }

  Json drive_json(const fleet::LineEntry& line, const fleet::DriveEntry& d) const {
    const DriveState* st = nullptr;
    static const DriveState kUnknown;
    auto it = states.find(d.name);
    st = it == states.end() ? &kUnknown : &it->second;
    Json j{{"name", d.name},
           {"line", line.name},
           {"id", d.id},
           {"status", st->status},
           {"last_backup", st->last_backup ? Json(iso_time(*st->last_backup)) : Json(nullptr)}};
    if (st->last_attempt) {
      j["last_attempt"] = {{"time", iso_time(*st->last_attempt)},
                           {"job", st->last_kind},
                           {"result", st->last_ok ? "ok" : "failed"},
                           {"exit_code", st->last_exit_code}};
    } else {
      j["last_attempt"] = nullptr;
    }
    j["differences"] = st->differences;
    j["message"] = st->message;
    if (st->status == "drift") j["differing"] = st->differing;
    return j;
  }
};

Service::Service(std::unique_ptr<Impl> impl) : impl_(std::move(impl)) {}

Result<std::unique_ptr<Service>> Service::create(ServiceOptions opt) {
  if (opt.links.size() != opt.inventory.lines.size())
    return Error(Errc::invalid_argument, "serve: one link per inventory line is needed");
  LMCFG_ASSIGN_OR_RETURN(auto archive, fleet::Archive::open(opt.archive, true));
  // A service killed during a commit (kill -9, power loss) leaves git's lock
  // files, and every later commit would fail on them. The archive is the
  // service's own (docs/serve.md): nobody else holds them now.
  LMCFG_ASSIGN_OR_RETURN(auto stale, archive.remove_stale_locks());
  for (const auto& f : stale)
    if (opt.log) opt.log("archive: removed the stale lock " + f + " (left by a stopped writer)");
  auto impl = std::make_unique<Impl>(std::move(opt), std::move(archive));
  impl->started = impl->opt.clock();
  const std::size_t n = impl->opt.inventory.lines.size();
  impl->queues.resize(n);
  impl->busy.assign(n, false);
  impl->line_metrics.resize(n);
  impl->state_dir = impl->opt.state_dir.empty()
                        ? std::filesystem::path(impl->opt.archive) / ".git" / "lmcfg-serve"
                        : std::filesystem::path(impl->opt.state_dir);
  Impl* p = impl.get();
  p->load_pending();
  for (std::size_t l = 0; l < n; ++l) impl->workers.emplace_back([p, l] { p->worker(l); });
  if (!impl->opt.inventory.archive.push.empty()) {
    // Commits of an earlier run that were not pushed yet (a failed push, a
    // stop or a kill before it went) go with the first push.
    auto head = impl->archive.resolve("HEAD");
    if (head.ok() && *head) impl->push.wanted = 1;
    impl->pusher = std::thread([p] { p->push_loop(); });
  }
  return std::unique_ptr<Service>(new Service(std::move(impl)));
}

Service::~Service() {
  stop();
  for (auto& w : impl_->workers) w.join();
  if (impl_->pusher.joinable()) impl_->pusher.join();
}

void Service::stop() {
  std::lock_guard<std::mutex> lock(impl_->mu);
  impl_->stopping = true;
  impl_->cv.notify_all();
  impl_->push_cv.notify_all();
}

void Service::wait_idle() {
  std::unique_lock<std::mutex> lock(impl_->mu);
  impl_->cv.wait(lock, [&] {
    if (impl_->stopping) return true;
    for (std::size_t l = 0; l < impl_->queues.size(); ++l)
      if (!impl_->queues[l].empty() || impl_->busy[l]) return false;
    return true;
  });
}

void Service::tick(TimePoint now) {
  summarize(now);
  auto& s = *impl_;
  const auto& sched = s.opt.inventory.schedule;
  std::lock_guard<std::mutex> lock(s.mu);
  if (s.stopping) return;
  auto due = [&](const std::optional<std::chrono::seconds>& every, std::optional<TimePoint>& next) {
    if (!every) return false;
    if (!next) next = now;  // the first tick
    if (now < *next) return false;
    while (*next <= now) *next += *every;  // periods missed while busy are not made up
    return true;
  };
  for (Kind kind : {Kind::backup, Kind::status}) {
    if (!due(kind == Kind::backup ? sched.backup_every : sched.status_every,
             kind == Kind::backup ? s.next_backup : s.next_status))
      continue;
    // A line still busy with a long job (a restore) gets one waiting run of a
    // kind, not one per period missed.
    std::vector<std::size_t> lines;
    for (std::size_t l = 0; l < s.opt.inventory.lines.size(); ++l) {
      const bool waiting = std::any_of(s.queues[l].begin(), s.queues[l].end(), [&](const Task& t) {
        return t.job && t.job->kind == kind && t.job->scope == "scheduled";
      });
      if (!waiting) lines.push_back(l);
    }
    if (lines.empty()) continue;
    auto job = s.new_job(kind, "scheduled");
    for (std::size_t l : lines) s.enqueue(l, job, {});
    s.log(std::string("scheduled ") + kind_name(kind) + " job " + job->id + ": " +
          std::to_string(job->total) + " drive(s) on " +
          std::to_string(s.opt.inventory.lines.size()) + " line(s)");
  }
}

std::optional<TimePoint> Service::next_backup() const {
  std::lock_guard<std::mutex> lock(impl_->mu);
  return impl_->next_backup;
}
std::optional<TimePoint> Service::next_status() const {
  std::lock_guard<std::mutex> lock(impl_->mu);
  return impl_->next_status;
}

Result<std::string> Service::backup_drive(const std::string& name, const std::string& who) {
  const fleet::LineEntry* line = nullptr;
  if (!impl_->opt.inventory.find_drive(name, &line))
    return Error(Errc::not_found, "no drive named '" + name + "' in the inventory");
  std::lock_guard<std::mutex> lock(impl_->mu);
  if (impl_->stopping) return Error(Errc::interrupted, "the service is stopping");
  auto job = impl_->new_job(Kind::backup, "drive " + name);
  job->who = who;
  impl_->enqueue(static_cast<std::size_t>(line - impl_->opt.inventory.lines.data()), job, {name});
  impl_->log("backup job " + job->id + " asked for: drive " + name);
  return job->id;
}

Result<std::string> Service::backup_line(const std::string& name, const std::string& who) {
  const auto& lines = impl_->opt.inventory.lines;
  for (std::size_t l = 0; l < lines.size(); ++l) {
    if (lines[l].name != name) continue;
    std::lock_guard<std::mutex> lock(impl_->mu);
    if (impl_->stopping) return Error(Errc::interrupted, "the service is stopping");
    auto job = impl_->new_job(Kind::backup, "line " + name);
    job->who = who;
    impl_->enqueue(l, job, {});
    impl_->log("backup job " + job->id + " asked for: line " + name);
    return job->id;
  }
  return Error(Errc::not_found, "no line named '" + name + "' in the inventory");
}

Result<Json> Service::job(const std::string& id) const {
  std::lock_guard<std::mutex> lock(impl_->mu);
  std::uint64_t number = 0;
  const auto [end, ec] = std::from_chars(id.data(), id.data() + id.size(), number);
  auto it = ec == std::errc() && end == id.data() + id.size() ? impl_->jobs.find(number)
                                                              : impl_->jobs.end();
  if (it == impl_->jobs.end()) return Error(Errc::not_found, "no job " + id);
  return impl_->job_json(*it->second);
}

Json Service::drives() const {
  std::lock_guard<std::mutex> lock(impl_->mu);
  Json all = Json::array();
  for (const auto& line : impl_->opt.inventory.lines)
    for (const auto& d : line.drives) all.push_back(impl_->drive_json(line, d));
  return all;
}

Result<Json> Service::drive(const std::string& name) const {
  const fleet::LineEntry* line = nullptr;
  const auto* d = impl_->opt.inventory.find_drive(name, &line);
  if (!d) return Error(Errc::not_found, "no drive named '" + name + "' in the inventory");
  std::lock_guard<std::mutex> lock(impl_->mu);
  return impl_->drive_json(*line, *d);
}

Result<Json> Service::history(const std::string& name) const {
  const auto* d = impl_->opt.inventory.find_drive(name);
  if (!d) return Error(Errc::not_found, "no drive named '" + name + "' in the inventory");
  std::lock_guard<std::mutex> lock(impl_->archive_mu);
  LMCFG_ASSIGN_OR_RETURN(auto events, fleet::position_history(impl_->archive, *d));
  return fleet::history_json(events);
}

const fleet::Inventory& Service::inventory() const { return impl_->opt.inventory; }

Result<Json> Service::plan(const std::string& name, const std::string& rev,
                           const std::string& who) {
  auto& s = *impl_;
  const fleet::LineEntry* line = nullptr;
  const auto* d = s.opt.inventory.find_drive(name, &line);
  if (!d) return Error(Errc::not_found, "no drive named '" + name + "' in the inventory");
  if (line->devicenet) {
    return Error(Errc::not_supported,
                 "drive " + name + " is a DeviceNet controller on line " + line->name +
                     ": the service restores LinRS drives; use lmcfg fleet restore");
  }
  StoredPlan sp;
  {
    std::lock_guard<std::mutex> lock(s.archive_mu);
    LMCFG_ASSIGN_OR_RETURN(sp.file, fleet::load_archived(s.opt.inventory, s.archive, name,
                                                         rev.empty() ? "HEAD" : rev));
  }
  sp.line = s.line_index(line);
  // The plan of `lmcfg restore --dry-run`, the values the target cannot take
  // listed apart (execute decides whether to leave them out).
  LMCFG_ASSIGN_OR_RETURN(sp.plan, s.on_worker<ops::Plan>(sp.line, [&]() -> Result<ops::Plan> {
    LMCFG_ASSIGN_OR_RETURN(auto session, link::open_session(s.link_for(sp.line, *d)));
    ops::RestoreRunOptions ro;
    ro.restore = s.restore_options(*line, *d, true);
    ro.dry_run = true;
    auto out = ops::run_restore(*session, sp.file.config, s.opt.db, ro);
    auto closed = session->close();
    if (out.stage == ops::RestoreOutcome::Stage::failed) return *out.error;
    if (!closed.ok()) return closed.error();
    return std::move(out.plan);
  }));
  sp.who = who;
  sp.id = random_id();
  sp.expires = s.opt.clock() + s.opt.plan_lifetime;
  std::lock_guard<std::mutex> lock(s.mu);
  // Expired plans go; a plan is small, but an API client looping on plan must not grow the map.
  const TimePoint now = s.opt.clock();
  std::erase_if(s.plans, [&](const auto& kv) { return kv.second.expires <= now; });
  Json j = s.plan_to_json(sp);
  s.log("plan " + sp.id + " for " + name + " <- " + sp.file.file_name + ": " +
        std::to_string(sp.plan.steps.size()) + " step(s), " +
        std::to_string(sp.plan.problems.size()) + " problem(s)" +
        (who.empty() ? "" : ", asked by " + who));
  s.plans.emplace(sp.id, std::move(sp));
  return j;
}

Result<std::string> Service::execute(const ExecuteRequest& req) {
  auto& s = *impl_;
  std::lock_guard<std::mutex> lock(s.mu);
  if (s.stopping) return Error(Errc::interrupted, "the service is stopping");
  auto it = s.plans.find(req.plan_id);
  if (it == s.plans.end()) return Error(Errc::not_found, "no plan '" + req.plan_id + "'");
  const TimePoint now = s.opt.clock();
  if (it->second.expires <= now) {
    const std::string when = iso_time(it->second.expires);
    s.plans.erase(it);
    return Error(Errc::not_found,
                 "plan '" + req.plan_id + "' expired at " + when + " (a plan is valid for " +
                     std::to_string(s.opt.plan_lifetime.count()) + " s): make a new one");
  }
  if (s.opt.inventory.require_reason && req.audit.reason.empty()) {
    return Error(Errc::invalid_argument,
                 "a reason is required (the inventory sets require_reason = true): give "
                 "\"reason\"");
  }
  const StoredPlan& sp = it->second;
  if (!sp.plan.ok()) {
    return Error(Errc::plan_refused, "plan '" + req.plan_id + "' has " +
                                         std::to_string(sp.plan.problems.size()) +
                                         " problem(s) (listed under \"problems\"); nothing "
                                         "written");
  }
  if (!sp.plan.skipped_incompatible.empty() && !req.skip_incompatible) {
    return Error(Errc::plan_refused,
                 "the target cannot take " + std::to_string(sp.plan.skipped_incompatible.size()) +
                     " value(s) of the file (listed under \"incompatible\"): execute with "
                     "\"skip_incompatible\": true to restore the rest; nothing written");
  }
  auto stored = std::make_shared<StoredPlan>(std::move(it->second));
  s.plans.erase(it);  // a plan executes once
  auto job = s.new_job(Kind::restore, "drive " + stored->file.drive->name);
  job->who = req.audit.who;
  job->total = 1;
  job->step_total = stored->plan.steps.size();
  Service::Impl* p = impl_.get();
  const ops::Audit audit = req.audit;
  const bool skip = req.skip_incompatible;
  s.queues[stored->line].push_back(Task{job, {}, [p, job, stored, audit, skip](bool run) {
                                          if (!run) return;
                                          p->run_restore_job(*job, stored->line, stored->file,
                                                             audit, skip, "", &stored->plan,
                                                             stored->id);
                                        }});
  s.cv.notify_all();
  s.log("restore job " + job->id + " asked for: plan " + stored->id + ", " +
        stored->file.drive->name + (audit.who.empty() ? "" : " by " + audit.who));
  return job->id;
}

namespace {

// Both sides of a position's diff and ops::diff()'s result, the position's
// ignored UPIDs left out: one computation for the JSON and the HTML answers.
struct DiffSides {
  fleet::ArchivedFile a;
  config::DriveConfig b;
  std::string b_name;
  ops::DiffResult r;
};

}  // namespace

static Result<DiffSides> diff_sides(Service::Impl& s, const std::string& name,
                                    const std::string& from, const std::string& to) {
  const fleet::LineEntry* line = nullptr;
  const auto* d = s.opt.inventory.find_drive(name, &line);
  if (!d) return Error(Errc::not_found, "no drive named '" + name + "' in the inventory");
  auto archived = [&](const std::string& rev) -> Result<fleet::ArchivedFile> {
    std::lock_guard<std::mutex> lock(s.archive_mu);
    return fleet::load_archived(s.opt.inventory, s.archive, name, rev.empty() ? "HEAD" : rev);
  };
  DiffSides out;
  LMCFG_ASSIGN_OR_RETURN(out.a, archived(from));
  if (to == "live") {
    const std::size_t li = s.line_index(line);
    LMCFG_ASSIGN_OR_RETURN(
        out.b, s.on_worker<config::DriveConfig>(li, [&]() -> Result<config::DriveConfig> {
          fleet::FleetOptions fo;
          fo.db = s.opt.db;
          fo.backup = s.opt.backup;
          auto run = fleet::read_line(*line, s.opt.links[li], fo, {name});
          if (run.configs.empty() || !run.configs[0]) {
            if (!run.drives.empty() && run.drives[0].error) return *run.drives[0].error;
            return Error(Errc::io_error, "drive " + name + " could not be read");
          }
          return std::move(*run.configs[0]);
        }));
    out.b_name = "drive " + name + " (live)";
  } else {
    LMCFG_ASSIGN_OR_RETURN(auto f, archived(to));
    out.b = std::move(f.config);
    out.b_name = f.file_name;
  }
  out.r = ops::diff(out.a.config, out.b, s.opt.db, nullptr, ops::DiffOptions{});
  // The position's live and volatile values are never a difference (as in drift checks).
  const auto ignored = fleet::ignored_upids(*line, *d);
  std::erase_if(out.r.items, [&](const ops::DiffItem& it) {
    return it.kind == ops::DiffItem::Kind::parameter &&
           std::find(ignored.begin(), ignored.end(), it.key) != ignored.end();
  });
  return out;
}

Result<Json> Service::diff(const std::string& name, const std::string& from,
                           const std::string& to) const {
  LMCFG_ASSIGN_OR_RETURN(auto d, diff_sides(*impl_, name, from, to));
  return Json::parse(ops::render_json(d.r, d.a.file_name, d.b_name));
}

Result<std::string> Service::diff_html(const std::string& name, const std::string& from,
                                       const std::string& to) const {
  LMCFG_ASSIGN_OR_RETURN(auto d, diff_sides(*impl_, name, from, to));
  report::ReportOptions ro;
  ro.generated_at = iso_time(impl_->opt.clock());
  return report::render_diff_report(d.a.config, d.a.file_name, d.b, d.b_name, d.r, impl_->opt.db,
                                    ro);
}

Result<std::string> Service::report_html(const std::string& name, const std::string& rev) const {
  auto& s = *impl_;
  if (!s.opt.inventory.find_drive(name))
    return Error(Errc::not_found, "no drive named '" + name + "' in the inventory");
  Result<fleet::ArchivedFile> f = [&] {
    std::lock_guard<std::mutex> lock(s.archive_mu);
    return fleet::load_archived(s.opt.inventory, s.archive, name, rev.empty() ? "HEAD" : rev);
  }();
  if (!f.ok()) return f.error();
  report::ReportOptions ro;
  ro.generated_at = iso_time(s.opt.clock());
  return report::render_report(f->config, f->file_name, s.opt.db, ro);
}

void Service::summarize(TimePoint now) {
  auto& s = *impl_;
  const std::int64_t day =
      std::chrono::duration_cast<std::chrono::seconds>(now.time_since_epoch()).count() / 86400;
  Json counts{{"ok", 0}, {"drift", 0}, {"failed", 0}, {"replaced", 0}, {"unknown", 0}};
  {
    std::lock_guard<std::mutex> lock(s.mu);
    if (!s.summary_day) {
      s.summary_day = day;  // the first day is summarized when it ends
      return;
    }
    if (day <= *s.summary_day) return;
    s.summary_day = day;
    for (const auto& line : s.opt.inventory.lines) {
      for (const auto& d : line.drives) {
        auto it = s.states.find(d.name);
        const std::string st = it == s.states.end() ? "unknown" : it->second.status;
        counts[st] = counts.value(st, 0) + 1;
      }
    }
  }
  s.emit("summary", "", "",
         {{"period", "day"}, {"drives", s.opt.inventory.drive_count()}, {"counts", counts}});
}

void Service::set_base_url(const std::string& url) {
  std::lock_guard<std::mutex> lock(impl_->mu);
  impl_->base_url = url;
}

std::string Service::metrics() const {
  const auto& s = *impl_;
  std::lock_guard<std::mutex> lock(s.mu);
  std::string o;
  auto head = [&](const char* name, const char* type, const char* help) {
    o += std::string("# HELP ") + name + " " + help + "\n# TYPE " + name + " " + type + "\n";
  };
  head("lmcfg_serve_uptime_seconds", "gauge", "Seconds since the service started.");
  o += "lmcfg_serve_uptime_seconds " +
       number(std::chrono::duration<double>(s.opt.clock() - s.started).count()) + "\n";
  auto per_drive = [&](const char* name, const char* type, const char* help, auto value) {
    head(name, type, help);
    for (const auto& line : s.opt.inventory.lines) {
      for (const auto& d : line.drives) {
        auto it = s.states.find(d.name);
        static const DriveState kUnknown;
        const DriveState& st = it == s.states.end() ? kUnknown : it->second;
        auto v = value(st);
        if (!v) continue;
        o += std::string(name) + "{drive=\"" + label(d.name) + "\",line=\"" + label(line.name) +
             "\"} " + number(*v) + "\n";
      }
    }
  };
  per_drive("lmcfg_drive_last_backup_timestamp_seconds", "gauge",
            "Time of the drive's last successful backup (Unix time).",
            [](const DriveState& st) -> std::optional<double> {
              if (!st.last_backup) return std::nullopt;
              return epoch_seconds(*st.last_backup);
            });
  per_drive("lmcfg_drive_last_attempt_success", "gauge",
            "1 when the last read of the drive (backup or drift check) succeeded, else 0.",
            [](const DriveState& st) -> std::optional<double> {
              if (!st.last_attempt) return std::nullopt;
              return st.last_ok ? 1 : 0;
            });
  per_drive("lmcfg_drive_last_attempt_exit_code", "gauge",
            "The CLI exit code of the last attempt's result (0 ok, 4 link, 5 drive refused).",
            [](const DriveState& st) -> std::optional<double> {
              if (!st.last_attempt) return std::nullopt;
              return st.last_exit_code;
            });
  per_drive(
      "lmcfg_drive_drift", "gauge", "1 when the drive differs from its archived file.",
      [](const DriveState& st) -> std::optional<double> { return st.status == "drift" ? 1 : 0; });
  per_drive("lmcfg_drive_differences", "gauge",
            "Differences between the drive and its archived file at the last check.",
            [](const DriveState& st) -> std::optional<double> {
              return static_cast<double>(st.differences);
            });
  auto per_line = [&](const char* name, const char* type, const char* help, auto value) {
    head(name, type, help);
    for (std::size_t l = 0; l < s.opt.inventory.lines.size(); ++l)
      o += std::string(name) + "{line=\"" + label(s.opt.inventory.lines[l].name) + "\"} " +
           number(value(s.line_metrics[l])) + "\n";
  };
  per_line("lmcfg_line_telegrams_total", "counter", "Telegrams sent on the line.",
           [](const LineMetrics& m) { return static_cast<double>(m.telegrams); });
  per_line("lmcfg_line_retries_total", "counter", "Telegrams repeated after a lost or bad answer.",
           [](const LineMetrics& m) { return static_cast<double>(m.retries); });
  per_line("lmcfg_line_timeouts_total", "counter", "Answers not received in time.",
           [](const LineMetrics& m) { return static_cast<double>(m.timeouts); });
  per_line("lmcfg_line_errors_total", "counter", "Drive reads on the line that failed.",
           [](const LineMetrics& m) { return static_cast<double>(m.errors); });
  per_line("lmcfg_line_runs_total", "counter", "Jobs run on the line.",
           [](const LineMetrics& m) { return static_cast<double>(m.runs); });
  per_line("lmcfg_line_run_seconds_total", "counter", "Seconds the line's jobs took in total.",
           [](const LineMetrics& m) { return m.run_seconds; });
  per_line("lmcfg_line_last_run_seconds", "gauge", "Seconds the line's last job took.",
           [](const LineMetrics& m) { return m.last_run_seconds; });
  if (s.opt.inventory.archive.push.empty()) return o;
  head("lmcfg_archive_push_pending", "gauge",
       "1 while a commit of the archive is not pushed to [archive] push yet, else 0.");
  o += "lmcfg_archive_push_pending " + number(s.push.wanted > s.push.done ? 1 : 0) + "\n";
  head("lmcfg_archive_push_failures_total", "counter", "Pushes of the archive that failed.");
  o += "lmcfg_archive_push_failures_total " + number(static_cast<double>(s.push.failures)) + "\n";
  head("lmcfg_archive_push_last_success_timestamp_seconds", "gauge",
       "Time of the last successful push of the archive (Unix time).");
  if (s.push.last_success)
    o += "lmcfg_archive_push_last_success_timestamp_seconds " +
         number(epoch_seconds(*s.push.last_success)) + "\n";
  return o;
}

}  // namespace lmcfg::serve
