#pragma once
// Private to the serve layer: the state of a Service and the steps its
// threads run, shared by service.cpp (the public calls), service_jobs.cpp
// (backups and drift checks on the line workers), service_restore.cpp
// (restore jobs and unfinished restores) and service_metrics.cpp (metrics,
// the daily summary, the archive's push thread). Not installed.
#include <filesystem>
#include <map>
#include <memory>
#include <mutex>
#include <optional>

#include "common/text.hpp"
#include "fleet/approved.hpp"
#include "fleet/archive.hpp"
#include "ops/recovery.hpp"
#include "ops/restore_run.hpp"
#include "serve/archive_push.hpp"
#include "serve/job_table.hpp"
#include "serve/line_workers.hpp"
#include "serve/plan_store.hpp"
#include "serve/service.hpp"
#include "serve/state_store.hpp"

namespace lmcfg::serve {

namespace detail {

// What a live read (service_live.cpp) answers: its JSON, and for a diff the
// drive as read (each request compares it with its own revision).
struct LiveAnswer {
  Json result;
  std::shared_ptr<const config::DriveConfig> live;
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
  // The parts, each with its own lock (docs/architecture.md "lmcfg serve"):
  //  - PlanStore -> JobTable -> LineWorkers is the only order in which one
  //    part's lock is held while the next's is taken (execute: a plan taken
  //    and its restore job made at once; a live read: its job shared or made
  //    while the line's queue is counted). Never the other way round.
  //  - StateStore, Pusher and `mu` (the schedule) are leaves: while one is
  //    held nothing else is locked.
  //  - archive_mu is held across libgit2 work only; StateStore's lock may be
  //    taken under it (compare_approved), never the reverse.
  //  - No lock is held while a drive is read or written: a line's worker
  //    runs its task with none, and takes each lock briefly to record.
  ServiceOptions opt;
  fleet::Archive archive;
  std::mutex archive_mu;  // libgit2's repository: one user at a time
  // pending/ (restores begun), lmcfg/ (recovery and undo records, laid out as
  // $XDG_STATE_HOME/lmcfg is for the CLI: XDG_STATE_HOME=<state_dir> lmcfg undo --list)
  std::filesystem::path state_dir;
  TimePoint started;

  mutable std::mutex mu;  // the schedule and base_url below
  std::optional<TimePoint> next_backup, next_status;
  std::optional<std::int64_t> summary_day;  // days since the epoch of the last summary
  std::string base_url;                     // set_base_url

  JobTable jobs;
  PlanStore plans;
  StateStore store;
  LineWorkers lines;
  std::unique_ptr<Pusher> pusher;  // with [archive] push only

  Impl(ServiceOptions o, fleet::Archive a, std::filesystem::path dir)
      : opt(std::move(o)),
        archive(std::move(a)),
        state_dir(std::move(dir)),
        jobs(state_dir, opt.clock, [this](const std::string& s) { log(s); }),
        plans(opt.clock, opt.plan_lifetime),
        store(state_dir, [this](const std::string& s) { log(s); }),
        lines(opt.inventory.lines.size()) {}

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

  // Caller holds store's lock (the `data` it gave). An automatic retry
  // failed: listed on `p` and counted.
  void note_retry_failed(const Job& job, const Error& e, PendingRestore& p,
                         StateStore::Data& data) const;

  // Every line escaped (log_text): names, reasons and paths a client sent
  // can neither start a line of their own nor reach the terminal raw.
  void log(const std::string& s) const {
    if (opt.log) opt.log(log_text(s));
  }
  int exit_code(const Error& e) const { return opt.exit_code ? opt.exit_code(e) : 70; }

  // A backup or drift check of `only` (empty: the whole line) on `line`'s
  // worker, counted into the job's totals; false (the job failed, saying
  // so) when the service is stopping.
  bool enqueue(std::size_t line, const std::shared_ptr<Job>& job, std::vector<std::string> only);
  // Other work on `line`'s worker (a restore, a live read): fn(true) there,
  // or fn(false) when the service stops first; false (nothing queued, the
  // job failed) when it is stopping already.
  bool enqueue_fn(std::size_t line, const std::shared_ptr<Job>& job,
                  std::function<void(bool run)> fn);
  // The job ended without running: the service stopped first.
  void stopped_before(Job& job);

  // A commit was made: with [archive] push, the push thread pushes it.
  void want_push() {
    if (pusher) pusher->want();
  }

  // An event about the archive, not a position: push_failed, push_recovered.
  void emit_archive(const std::string& event, Json details);

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
  std::string record_restore_state(StateStore::Data& data, const std::string& name,
                                   const RestoreAttempt& a, int code, const std::string& file_name,
                                   Json& details);

  // One drive's outcome: its state, and an event when the state changed.
  // `r` is the drive compared with its approved configuration.
  void record(Kind kind, const fleet::DriveResult& r, const std::optional<std::string>& commit);
  void record_state(DriveState& st, Kind kind, const fleet::DriveResult& r,
                    const std::optional<std::string>& commit, TimePoint now, const std::string& url,
                    std::string& event, Json& details) const;

  // Approved configurations (service_approved.cpp). Caller holds archive_mu:
  // after a backup's commit, the positions read without an approval get one
  // (commissioning); each read drive compared with its approved configuration
  // into la.against, the approvals into the states.
  Result<void> compare_approved(const fleet::LineEntry& line, const Job& job,
                                const std::string& before, fleet::LineRun& run, LineArchived& la);
  // The revision a restore without one takes: the approved one (HEAD when none).
  // Caller holds archive_mu.
  Result<std::string> restore_rev(const fleet::DriveEntry& d) const;
  // Caller holds store's lock (the `data` it gave). After a restore of a revision other than the
  // approved one: the position is in drift (the next check lists the differences).
  static void note_unapproved(StateStore::Data& data, const std::string& name,
                              const fleet::ArchivedFile& f);

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
  static void count_job(Job& job, const fleet::LineRun& run, const LineArchived& la, TimePoint now);

  // on_replaced = "restore": the archived file at HEAD, restored at once on this worker.
  void restore_replaced(std::size_t li, const fleet::DriveEntry& d);

  // Restores a previous run began and did not finish (killed, or stopped by a
  // signal mid-restore): loaded at start and queued first on their lines.
  void queue_pending();

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

  // A line's worker runs `task` (LineWorkers::Run); the tasks a stop left.
  void run_on_line(std::size_t line, Task& task);
  void drop_tasks(std::deque<Task>& left);

  // A plan for the API: the CLI's plan_json items (restore --dry-run --json),
  // each step with its `kind` and the old and new values for people.
  Json plan_to_json(const StoredPlan& sp) const;

  // A position's state, as GET /api/v1/drives/NAME answers it.
  Json drive_json(const fleet::LineEntry& line, const fleet::DriveEntry& d) const;
  // Every position's, as the text of dump(2) of the array of them, written
  // without the objects (config/json_writer.hpp).
  std::string drives_text() const;
  // Both through one statement of the members: W is config::JsonBuilder or
  // config::JsonTextWriter.
  template <class W>
  void write_drive(W& w, const fleet::LineEntry& line, const fleet::DriveEntry& d) const;
  template <class W>
  void write_retry(W& w, const std::string& name, const PendingRestore& pr) const;
};

}  // namespace lmcfg::serve
