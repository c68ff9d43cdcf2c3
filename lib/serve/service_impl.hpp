#pragma once
// Private to the serve layer: the state of a Service and the steps its
// threads run, shared by service.cpp (the public calls), service_jobs.cpp
// (backups and drift checks on the line workers), service_restore.cpp
// (restore jobs and unfinished restores) and service_metrics.cpp (metrics,
// the daily summary, the archive's push thread). Not installed.
#include <condition_variable>
#include <deque>
#include <filesystem>
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

// diff, plan: a live read asked for through the API (service_live.cpp).
enum class Kind { backup, status, restore, diff, plan };
inline const char* kind_name(Kind k) {
  switch (k) {
    case Kind::backup:
      return "backup";
    case Kind::status:
      return "status";
    case Kind::restore:
      return "restore";
    case Kind::diff:
      return "diff";
    case Kind::plan:
      return "plan";
  }
  return "backup";
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
  // The values the restore left as the drive holds them by policy
  // (ops::Plan::kept as ops::kept_json), each with its reason and remedy.
  Json kept = Json::array();
  // After a failed restore: what the drive holds now, in plain words (drive_state_after).
  std::string drive_state;
  // A live read (diff to=live, plan) for API requests: the requests asking the
  // same question share it (`key`); what it read (a diff's drive), its answer
  // (`result`, or `error`), and whether a request was given it (the next one
  // reads the drive again).
  std::string key;
  std::shared_ptr<const config::DriveConfig> live;
  Json result;
  std::optional<Error> error;
  bool handed = false;
};

// What a live read (service_live.cpp) answers: its JSON, and for a diff the
// drive as read (each request compares it with its own revision).
struct LiveAnswer {
  Json result;
  std::shared_ptr<const config::DriveConfig> live;
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
  // The automatic retries that failed: the newest kRetryFailuresKept (when,
  // which job, why), and how many in all.
  struct Failure {
    std::string time, job, reason;
  };
  std::vector<Failure> failures;
  std::size_t failed_attempts = 0;
};
inline constexpr std::size_t kRetryFailuresKept = 10;

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
  // What differs but is kept by policy (ops/matching.hpp), as ops::kept_json:
  // not drift, said on the position.
  Json kept = Json::array();
  // After a failed restore: what the drive holds (drive_state_after); "" otherwise.
  std::string drive_state;
  std::uint64_t retries_failed = 0;  // automatic retries of a restore that failed (a counter)
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

// A plan's id: 128 random bits in hex (service.cpp).
std::string random_plan_id();

// What a restore job did: the outcome, the error that ends it, the commit
// that records it.
struct RestoreAttempt {
  ops::RestoreOutcome out;
  std::optional<Error> err;
  std::optional<fleet::CommitInfo> record;
  bool unopened = false;    // the line could not be opened: nothing reached the drive
  std::string drive_state;  // after a failure: what the drive holds (drive_state_after)
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
  // Job numbers outlive a restart (<state_dir>/jobs.json holds the first
  // number the next start may use, reserved ahead in blocks): first_job is
  // this run's first; the file is written when next_job reaches reserved_job.
  std::uint64_t first_job = 1, reserved_job = 0;
  std::vector<std::deque<Task>> queues;  // one per line
  std::vector<bool> busy;
  bool stopping = false;
  std::size_t live_waiting = 0;  // HTTP workers waiting for a live read now (under mu)
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

  // A live read for an API request (service_live.cpp): `read` runs on the
  // line's worker as a job of `kind` (the drive read, the answer into the
  // job); requests with the same `key` share one. The caller (an HTTP
  // worker) waits at most opt.live_wait, and only while fewer than
  // opt.live_waiters others wait: the finished job, or the line_busy error
  // naming it (HTTP 503 with Retry-After). No lock is held while it waits.
  Result<std::shared_ptr<Job>> live_read(Kind kind, std::size_t line, const std::string& name,
                                         const std::string& key, const std::string& who,
                                         std::function<Result<LiveAnswer>()> read);
  // The line's worker: the live read of `job`, its end recorded.
  void run_live(std::size_t line, Job& job, const std::function<Result<LiveAnswer>()>& read);
  // A live read's answer to the request that waited for it: the job's result or error.
  static Result<Json> live_answer(const Job& job);
  // On the line's worker: the restore plan of `f` against the drive at `d`,
  // stored for execute(); its JSON (plan_to_json). `known_types`: the types
  // the position's latest backup recorded, for values the database cannot type.
  Result<LiveAnswer> make_plan(std::size_t li, const fleet::DriveEntry& d,
                               const fleet::ArchivedFile& f,
                               const std::map<std::uint16_t, std::uint8_t>& known_types,
                               const std::string& who);

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
  // Caller holds mu. An automatic retry failed: listed on `p` and counted.
  void note_retry_failed(const Job& job, const Error& e, PendingRestore& p);
  void remove_pending(const fleet::LineEntry& line, const fleet::DriveEntry& d);
  bool is_pending(const std::string& name) const {
    std::lock_guard<std::mutex> lock(mu);
    return pending.count(name) != 0;
  }

  // Caller holds mu. A restore job on position `name` queued or running now, if any.
  const Job* unfinished_restore(const std::string& name) const {
    for (const auto& [num, job] : jobs)
      if (job->kind == Kind::restore && !job->finished && job->position == name) return job.get();
    return nullptr;
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

  // Caller holds mu.
  std::shared_ptr<Job> new_job(Kind kind, std::string scope) {
    auto j = std::make_shared<Job>();
    const std::uint64_t number = next_job++;
    if (number >= reserved_job) reserve_jobs(number);
    j->id = std::to_string(number);
    j->kind = kind;
    j->scope = std::move(scope);
    j->created = opt.clock();
    jobs[number] = j;
    // The newest 1000 jobs are kept for GET /jobs/{id}.
    while (jobs.size() > 1000) jobs.erase(jobs.begin());
    return j;
  }
  // Job numbers across restarts (service_jobs.cpp): read at start; the next
  // block from `number` on written (caller holds mu; a failure is logged).
  void load_job_numbers();
  void reserve_jobs(std::uint64_t number);
  // Caller holds mu. Why job `id` is not there: ended before the service
  // restarted, no longer kept, or never made.
  std::string missing_job(const std::string& id, std::uint64_t number) const;
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
