#pragma once
// Private to the serve layer: the service's jobs (docs/serve.md "Jobs") and
// the table that keeps them, by number, under its own lock. Not installed.
#include <chrono>
#include <condition_variable>
#include <cstdint>
#include <filesystem>
#include <functional>
#include <map>
#include <memory>
#include <mutex>
#include <optional>
#include <string>
#include <vector>

#include "serve/service.hpp"

namespace lmcfg::serve::detail {

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

// One job. Its id, kind, scope, position, created, key, retry_of and
// asked_by are set before the job is in a table and never change; every
// other field is read and written under its table's lock (JobTable::update).
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

// A job as GET /api/v1/jobs/{id} shows it (without "retry_pending", which is
// the state store's). Caller holds the job's table lock.
Json job_json(const Job& j);

// The jobs by number, the newest kJobsKept; numbers outlive a restart
// (<state_dir>/jobs.json holds the first number the next start may use,
// reserved ahead in blocks, so the file is written once per block).
class JobTable {
 public:
  static constexpr std::size_t kJobsKept = 1000;

  JobTable(std::filesystem::path state_dir, std::function<TimePoint()> clock,
           std::function<void(const std::string&)> log);

  // Reads jobs.json (at start, before any job is made).
  void load();

  // A new job: `init` sets its fixed fields (who, key, retry_of...) before
  // anyone else can see it.
  std::shared_ptr<Job> add(Kind kind, std::string scope, std::string position = "",
                           const std::function<void(Job&)>& init = {});

  // `f(job)` under the table's lock; waiters on a job (wait_finished) wake.
  template <class F>
  decltype(auto) update(Job& job, F&& f) {
    std::lock_guard<std::mutex> lock(mu_);
    struct Wake {
      std::condition_variable& cv;
      ~Wake() { cv.notify_all(); }
    } wake{cv_};
    return f(job);
  }
  // `f(job)` under the table's lock, reading.
  template <class F>
  decltype(auto) read(const Job& job, F&& f) const {
    std::lock_guard<std::mutex> lock(mu_);
    return f(job);
  }

  // GET /api/v1/jobs/{id}: job_json, and the job's position and state for
  // the caller's additions; Errc::not_found saying why the job is not there.
  struct Shown {
    Json json;
    Kind kind = Kind::backup;
    std::string position;
    bool failed = false;
  };
  Result<Shown> show(const std::string& id) const;

  // The newest job with `key` that `reusable` accepts, else a new one made
  // by add() when `admit` lets it (its error otherwise). Under the lock
  // throughout, so two requests asking the same question share one job;
  // `admit` may take LineWorkers' lock (the order is in service_impl.hpp).
  struct Shared {
    std::shared_ptr<Job> job;
    bool made = false;
  };
  Result<Shared> share(const std::string& key, const std::function<bool(const Job&)>& reusable,
                       const std::function<Result<void>()>& admit, Kind kind,
                       const std::string& position, const std::function<void(Job&)>& init);

  // Waits at most `wait` for `job` to finish, and only while fewer than
  // `max_waiters` others wait here (the HTTP server's workers stay free);
  // true when it has finished (it is then marked handed). A job the caller
  // has just `made` is its answer only when the caller may wait for it: one
  // that may not is told "busy" however fast the read, and its answer goes to
  // the same request asked again.
  bool wait_finished(Job& job, std::chrono::milliseconds wait, std::size_t max_waiters, bool made);
  // Waiters give up now: the service stops.
  void stop();

  // A restore job of position `name` queued or running; the words for a
  // refusal naming it ("" when none), read under the lock.
  std::optional<std::string> unfinished_restore(const std::string& name) const;
  // A restore job running on `name` now: its id ("" when none).
  std::string running_restore(const std::string& name) const;
  // A new restore job of `name` unless one is unfinished: the job, or the
  // words unfinished_restore gives (under the lock throughout).
  Result<std::shared_ptr<Job>> add_restore(const std::string& name,
                                           const std::function<void(Job&)>& init);

 private:
  // Caller holds mu_. Why job `id` (number `number`, 0 when not a number) is not there.
  std::string missing(const std::string& id, std::uint64_t number) const;
  std::shared_ptr<Job> add_locked(Kind kind, std::string scope, std::string position,
                                  const std::function<void(Job&)>& init);
  const Job* unfinished_locked(const std::string& name) const;
  void reserve(std::uint64_t number);

  const std::filesystem::path dir_;
  const std::function<TimePoint()> clock_;
  const std::function<void(const std::string&)> log_;
  mutable std::mutex mu_;
  std::condition_variable cv_;
  std::map<std::uint64_t, std::shared_ptr<Job>> jobs_;  // begin() is the oldest
  std::uint64_t next_ = 1, first_ = 1, reserved_ = 0;
  std::size_t waiting_ = 0;
  bool stopping_ = false;
};

}  // namespace lmcfg::serve::detail
