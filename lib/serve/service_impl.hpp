#pragma once
// Private to the serve layer: the state of a Service and the steps its
// threads run, shared by service.cpp (the public calls), service_jobs.cpp
// (backups and drift checks on the line workers), service_restore.cpp
// (restore jobs and unfinished restores) and service_metrics.cpp (metrics,
// the daily summary, the archive's push thread). Not installed.
#include <condition_variable>
#include <deque>
#include <filesystem>
#include <future>
#include <map>
#include <mutex>
#include <optional>
#include <thread>

#include "common/text.hpp"
#include "fleet/approved.hpp"
#include "fleet/archive.hpp"
#include "ops/recovery.hpp"
#include "ops/restore_run.hpp"
#include "serve/service.hpp"

namespace lmcfg::serve {

namespace detail {

enum class Kind { backup, status, restore };
inline const char* kind_name(Kind k) {
  return k == Kind::backup ? "backup" : (k == Kind::status ? "status" : "restore");
}

inline double epoch_seconds(TimePoint t) {
  return std::chrono::duration<double>(t.time_since_epoch()).count();
}

struct Job {
  std::string id;
  Kind kind = Kind::backup;
  std::string scope;     // "drive NAME", "line NAME", "scheduled"
  std::string position;  // a drive job's position (NAME of its scope); "" otherwise
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
  // An automatic retry of a failed restore: the job that failed first and who asked for it.
  std::string retry_of, asked_by;
  // The values a restore left out (Plan::skipped_incompatible), each with its reason.
  std::vector<std::string> skipped;
  // After a failed restore: what the drive holds now, in plain words (drive_state_after).
  std::string drive_state;
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
  // The job that began it (an automatic retry says "automatic retry of job N"),
  // and what the drive held when it stopped (drive_state_after).
  std::string origin_job, drive_state;
};

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
  std::vector<std::string> differing;       // the differences, as the commit message says them
  std::string notified;                     // the last state an event was sent for
  std::optional<fleet::Approval> approved;  // the position's approved configuration, when known
  // After a failed restore: what the drive holds (drive_state_after); "" otherwise.
  std::string drive_state;
};

struct LineMetrics {
  std::uint64_t telegrams = 0, retries = 0, timeouts = 0, errors = 0, runs = 0;
  double run_seconds = 0, last_run_seconds = 0;
};

// Factory state as LinRS can see it (service_jobs.cpp): a configuration read
// from the drive, and what a restore plan read of the target.
bool factory_fresh(const config::DriveConfig& cfg, const db::Database& db,
                   const std::vector<std::uint16_t>& ignored);
bool factory_fresh(const ops::TargetSeen& t, const db::Database& db,
                   const std::vector<std::uint16_t>& ignored);

// What a restore job did: the outcome, the error that ends it, the commit
// that records it.
struct RestoreAttempt {
  ops::RestoreOutcome out;
  std::optional<Error> err;
  std::optional<fleet::CommitInfo> record;
};

// What archiving a line's run decided, per drive of the run.
struct LineArchived {
  explicit LineArchived(std::size_t n) : replaced(n, false), unfinished(n, false), against(n) {}
  std::vector<bool> replaced, unfinished;
  // Each drive compared with its approved configuration (the position's
  // status); nullopt: not compared (failed read).
  std::vector<std::optional<fleet::DriveResult>> against;
  std::optional<std::string> commit;
  Result<void> archived;
};

}  // namespace detail

// Only the service*.cpp files include this header.
using namespace detail;  // NOLINT(google-build-using-namespace)

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

  std::mutex archive_mu;      // libgit2's repository: one user at a time
  std::mutex states_file_mu;  // <state_dir>/states.json: one writer at a time
  std::string base_url;       // under mu: set_base_url

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
      queues[line].push_back(Task{nullptr, {}, [this, line, promise, fn](bool run) {
                                    if (!run) {
                                      promise->set_value(
                                          Error(Errc::interrupted, "the service is stopping"));
                                      return;
                                    }
                                    // The caller waits on the promise: a throw answers it too.
                                    std::optional<std::string> threw;
                                    try {
                                      promise->set_value(fn());
                                      return;
                                    } catch (const std::exception& e) {
                                      threw = e.what();
                                    } catch (...) {
                                      threw = "an exception of unknown type";
                                    }
                                    promise->set_value(thrown_error(line, *threw));
                                  }});
      cv.notify_all();
    }
    return future.get();
  }

  // What a task that threw fails with; logged.
  Error thrown_error(std::size_t line, const std::string& what) const {
    log("line " + opt.inventory.lines[line].name + ": a task threw (" + what +
        "); it failed, the service goes on");
    return Error(Errc::cancelled, "internal error on line " + opt.inventory.lines[line].name +
                                      ": " + one_line(what) +
                                      "; nothing more was done for this request (a bug: "
                                      "please report it with the service's log)");
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
                            const PendingRestore& p);
  void remove_pending(const fleet::LineEntry& line, const fleet::DriveEntry& d);
  bool is_pending(const std::string& name) const {
    std::lock_guard<std::mutex> lock(mu);
    return pending.count(name) != 0;
  }

  // Caller holds mu. The restore job running on position `name` now, if any.
  const Job* running_restore(const std::string& name) const {
    for (const auto& [num, job] : jobs)
      if (job->kind == Kind::restore && job->started && !job->finished &&
          job->scope == "drive " + name)
        return job.get();
    return nullptr;
  }

  // Every line escaped (log_text): names, reasons and paths a client sent
  // can neither start a line of their own nor reach the terminal raw.
  void log(const std::string& s) const {
    if (opt.log) opt.log(log_text(s));
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
  // A job about one position: its scope says "drive NAME", its position is NAME.
  std::shared_ptr<Job> new_drive_job(Kind kind, const std::string& name) {
    auto j = new_job(kind, "drive " + name);
    j->position = name;
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
  void emit_archive(const std::string& event, Json details);

  // The push thread. Its own handle on the repository: a slow or unreachable
  // remote holds neither archive_mu nor a line's worker, so backups and
  // commits go on and only the push waits.
  void push_loop();

  void emit(const std::string& event, const std::string& drive, const std::string& line,
            Json details) {
    Json j{{"event", event},
           {"drive", drive.empty() ? Json(nullptr) : Json(drive)},
           {"line", line.empty() ? Json(nullptr) : Json(line)},
           {"time", iso_time(opt.clock())}};
    for (auto& [k, v] : details.items()) j[k] = v;
    log("event " + event + (drive.empty() ? "" : ": " + drive + " (line " + line + ")"));
    notify(j);
  }
  // The event to opt.notify; what it throws is logged, never passed on (the
  // caller is a line's worker, the push thread or the schedule).
  void notify(const Json& j) const {
    if (!opt.notify) return;
    try {
      opt.notify(j);
    } catch (const std::exception& e) {
      log(std::string("event not sent: ") + e.what());
    } catch (...) {
      log("event not sent: an exception of unknown type");
    }
  }
  void emit(const std::string& event, const fleet::DriveResult& r, Json details) {
    emit(event, r.name, r.line, std::move(details));
  }

  // A factory-fresh drive where the archive holds a file: state `replaced`,
  // the event once.
  void record_replaced(Kind kind, const fleet::DriveResult& r, bool restoring);

  // Runs a restore of `f` on this line's worker thread (the caller is it):
  // the normal restore (plan against the target, undo record, execute,
  // verify), recorded as a commit with the audit trailers. `planned`: the plan
  // the API showed; the target must still read as it found it.
  void run_restore_job(Job& job, std::size_t li, const fleet::ArchivedFile& f,
                       const ops::Audit& audit, bool skip, const std::string& cause,
                       const ops::Plan* planned, const std::string& plan_id);
  // Its steps (service_restore.cpp): open, restore and commit; the options of
  // the restore; the job's and the position's state with the event.
  void attempt_restore(RestoreAttempt& a, Job& job, std::size_t li, const fleet::ArchivedFile& f,
                       const ops::Audit& audit, bool skip, const std::string& cause,
                       const ops::Plan* planned, const std::string& plan_id);
  ops::RestoreRunOptions restore_run_options(Job& job, std::size_t li, const fleet::DriveEntry& d,
                                             bool skip, const ops::Plan* planned,
                                             const std::string& plan_id);
  void finish_restore_job(Job& job, std::size_t li, const fleet::ArchivedFile& f,
                          const ops::Audit& audit, const std::string& cause,
                          const RestoreAttempt& a, bool interrupted);
  std::string record_restore_state(const std::string& name, const RestoreAttempt& a, int code,
                                   const std::string& file_name, Json& details);

  // One drive's outcome: its state, and an event when the state changed.
  // `r` is the drive compared with its approved configuration.
  void record(Kind kind, const fleet::DriveResult& r, const std::optional<std::string>& commit);

  // Approved configurations (service_approved.cpp). Caller holds archive_mu:
  // after a backup's commit, the positions read without an approval get one
  // (commissioning); each read drive compared with its approved configuration
  // into la.against, the approvals into the states.
  Result<void> compare_approved(const fleet::LineEntry& line, const Job& job,
                                const std::string& before, fleet::LineRun& run, LineArchived& la);
  // The revision a restore without one takes: the approved one (HEAD when none).
  // Caller holds archive_mu.
  Result<std::string> restore_rev(const fleet::DriveEntry& d) const;
  // The states as they are now, written to <state_dir>/states.json; and read
  // back at start (with the last backups of positions it does not name taken
  // from the archive's history), so a restart changes nothing people see.
  void save_states();
  void load_states();
  // Caller holds mu. After a restore of a revision other than the approved
  // one: the position is in drift (the next check lists the differences).
  void note_unapproved(const std::string& name, const fleet::ArchivedFile& f);

  // A backup or drift check of a line (a Task with a job), on its worker.
  void run_task(std::size_t line_index, Task& task);
  // Its steps (service_jobs.cpp): the unfinished restores of the line first;
  // the run compared with and (a backup) committed to the archive, archive_mu
  // held; each drive's state; the line's metrics and the job's counts.
  void resume_waiting(std::size_t li, const std::vector<std::string>& only);
  Result<void> archive_run(const fleet::LineEntry& line, const Job& job, fleet::LineRun& run,
                           LineArchived& la);
  std::size_t record_run(const fleet::LineEntry& line, Kind kind, fleet::LineRun& run,
                         LineArchived& la, std::vector<std::size_t>& to_restore);
  void count_run(std::size_t li, Job& job, const fleet::LineRun& run, const LineArchived& la,
                 std::size_t failed);

  // on_replaced = "restore": the archived file at HEAD, restored at once on this worker.
  void restore_replaced(std::size_t li, const fleet::DriveEntry& d);

  // Restores a previous run began and did not finish (killed, or stopped by a
  // signal mid-restore): loaded at start and queued first on their lines.
  void load_pending();

  // Runs the unfinished restores of `names` again (on this line's worker): the
  // same revision, who and why. Running a restore again converges
  // (docs/restore.md); one stopped by a link failure (the drive was resetting
  // or saving to flash when the service died) stays pending for the next run.
  void resume(std::size_t li, const std::vector<std::string>& names);

  // `code`: the exit code the job's record shows (default: exit_code(e)).
  void fail_job(Job& job, const Error& e, std::optional<int> code = std::nullopt);
  // A task that threw (a bug, or a library throwing where it should return an
  // error): its job fails with `what`, it is logged, the worker goes on.
  void task_threw(std::size_t line, Task& task, const std::string& what);

  void worker(std::size_t line);

  Json job_json(const Job& j) const;

  // A plan for the API: the CLI's plan_json items (restore --dry-run --json),
  // each step with its `kind` and the old and new values for people.
  Json plan_to_json(const StoredPlan& sp) const;

  Json drive_json(const fleet::LineEntry& line, const fleet::DriveEntry& d) const;
};

}  // namespace lmcfg::serve
