// The service's jobs (docs/serve.md "Jobs"): numbered across restarts, the
// newest kept for GET /api/v1/jobs/{id}, each job's fields under the table's
// lock, and the bounded wait of a request for a live read.
#include "serve/job_table.hpp"

#include <charconv>

#include "config/atomic_file.hpp"

namespace lmcfg::serve::detail {

namespace {
// Job numbers reserved at a time: jobs.json is written once per block.
constexpr std::uint64_t kJobBlock = 100;
}  // namespace

JobTable::JobTable(std::filesystem::path state_dir, std::function<TimePoint()> clock,
                   std::function<void(const std::string&)> log)
    : dir_(std::move(state_dir)), clock_(std::move(clock)), log_(std::move(log)) {}

void JobTable::load() {
  const auto path = dir_ / "jobs.json";
  std::error_code ec;
  if (!std::filesystem::exists(path, ec)) return;
  auto text = config::read_text_file(path, 1 << 16);
  const Json j = text.ok() ? Json::parse(*text, nullptr, false) : Json();
  if (!j.is_object() || !j.contains("next") || !j["next"].is_number_unsigned() ||
      j["next"].get<std::uint64_t>() == 0) {
    log_("jobs: " + path.string() + " is not a job numbers file of lmcfg serve; jobs start at 1");
    return;
  }
  std::lock_guard<std::mutex> lock(mu_);
  first_ = next_ = j["next"].get<std::uint64_t>();
}

// Caller holds mu_. A failure costs the numbering after a restart (it starts
// again below), not the job.
void JobTable::reserve(std::uint64_t number) {
  reserved_ = number + kJobBlock;
  std::error_code ec;
  std::filesystem::create_directories(dir_, ec);
  const Json file{{"format", "lmcfg-serve-jobs"}, {"version", 1}, {"next", reserved_}};
  if (auto w = config::write_file_atomic(dir_ / "jobs.json", file.dump(1) + "\n"); !w.ok())
    log_("jobs: " + w.error().message);
}

std::shared_ptr<Job> JobTable::add_locked(Kind kind, std::string scope, std::string position,
                                          const std::function<void(Job&)>& init) {
  auto j = std::make_shared<Job>();
  const std::uint64_t number = next_++;
  if (number >= reserved_) reserve(number);
  j->id = std::to_string(number);
  j->kind = kind;
  j->scope = std::move(scope);
  j->position = std::move(position);
  j->created = clock_();
  if (init) init(*j);
  jobs_[number] = j;
  while (jobs_.size() > kJobsKept) jobs_.erase(jobs_.begin());
  return j;
}

std::shared_ptr<Job> JobTable::add(Kind kind, std::string scope, std::string position,
                                   const std::function<void(Job&)>& init) {
  std::lock_guard<std::mutex> lock(mu_);
  return add_locked(kind, std::move(scope), std::move(position), init);
}

Result<JobTable::Shown> JobTable::show(const std::string& id) const {
  std::uint64_t number = 0;
  const auto [end, ec] = std::from_chars(id.data(), id.data() + id.size(), number);
  if (ec != std::errc() || end != id.data() + id.size()) number = 0;
  std::lock_guard<std::mutex> lock(mu_);
  auto it = jobs_.find(number);
  if (it == jobs_.end()) return Error(Errc::not_found, missing(id, number));
  const Job& j = *it->second;
  return Shown{job_json(j), j.kind, j.position, j.failed_job};
}

// Caller holds mu_.
std::string JobTable::missing(const std::string& id, std::uint64_t number) const {
  if (number == 0 || number >= next_) return "no job " + id;
  if (number < first_)
    return "job " + id +
           " ended before the service restarted: its record is not kept across "
           "a restart; the position's history lists what it did";
  return "job " + id +
         " is no longer kept (the service keeps its newest 1000 jobs); the "
         "position's history lists what it did";
}

Result<JobTable::Shared> JobTable::share(const std::string& key,
                                         const std::function<bool(const Job&)>& reusable,
                                         const std::function<Result<void>()>& admit, Kind kind,
                                         const std::string& position,
                                         const std::function<void(Job&)>& init) {
  std::lock_guard<std::mutex> lock(mu_);
  for (auto it = jobs_.rbegin(); it != jobs_.rend(); ++it) {
    const auto& j = it->second;
    if (j->key != key) continue;
    if (reusable(*j)) return Shared{j, false};
    break;
  }
  LMCFG_TRY(admit());
  return Shared{add_locked(kind, "drive " + position, position, init), true};
}

bool JobTable::wait_finished(Job& job, std::chrono::milliseconds wait, std::size_t max_waiters,
                             bool made) {
  std::unique_lock<std::mutex> lock(mu_);
  const bool may_wait = waiting_ < max_waiters && !stopping_;
  if (made && !may_wait) return false;
  if (!job.finished && may_wait) {
    ++waiting_;
    cv_.wait_for(lock, wait, [&] { return job.finished.has_value() || stopping_; });
    --waiting_;
  }
  if (!job.finished) return false;
  job.handed = true;
  return true;
}

void JobTable::stop() {
  std::lock_guard<std::mutex> lock(mu_);
  stopping_ = true;
  cv_.notify_all();
}

const Job* JobTable::unfinished_locked(const std::string& name) const {
  for (const auto& [num, job] : jobs_)
    if (job->kind == Kind::restore && !job->finished && job->position == name) return job.get();
  return nullptr;
}

namespace {
// Another technician's restore of the position, queued or running: a plan
// made before it wrote would be refused then; say who now.
std::string other_restore_words(const Job& other) {
  const std::string by = !other.asked_by.empty() ? other.asked_by : other.who;
  return "another restore of drive " + other.position + " is " +
         (other.started ? "running" : "waiting for the line") + " as job " + other.id +
         (by.empty() ? "" : ", asked for by " + by) + " at " + iso_time(other.created) +
         "; nothing written: wait for it to end (GET /api/v1/jobs/" + other.id +
         "), then plan again";
}
}  // namespace

std::optional<std::string> JobTable::unfinished_restore(const std::string& name) const {
  std::lock_guard<std::mutex> lock(mu_);
  if (const Job* other = unfinished_locked(name)) return other_restore_words(*other);
  return std::nullopt;
}

Result<std::shared_ptr<Job>> JobTable::add_restore(const std::string& name,
                                                   const std::function<void(Job&)>& init) {
  std::lock_guard<std::mutex> lock(mu_);
  if (const Job* other = unfinished_locked(name))
    return Error(Errc::plan_refused, other_restore_words(*other));
  return add_locked(Kind::restore, "drive " + name, name, init);
}

std::string JobTable::running_restore(const std::string& name) const {
  std::lock_guard<std::mutex> lock(mu_);
  for (const auto& [num, job] : jobs_)
    if (job->kind == Kind::restore && job->started && !job->finished &&
        job->scope == "drive " + name)
      return job->id;
  return "";
}

Json job_json(const Job& j) {
  const char* state =
      j.finished ? (j.failed_job ? "failed" : "done") : (j.started ? "running" : "queued");
  Json out{{"id", j.id},
           {"kind", kind_name(j.kind)},
           {"scope", j.scope},
           {"position", j.position.empty() ? Json(nullptr) : Json(j.position)},
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
    out["automatic"] =
        !j.retry_of.empty() || (!j.who.empty() && j.who.rfind("lmcfg serve", 0) == 0);
    out["retry_of"] = j.retry_of.empty() ? Json(nullptr) : Json(j.retry_of);
    out["asked_by"] = j.asked_by.empty() ? Json(nullptr) : Json(j.asked_by);
    out["skipped"] = j.skipped;
    out["kept"] = j.kept;
    out["drive_state"] = j.drive_state.empty() ? Json(nullptr) : Json(j.drive_state);
    return out;
  }
  if (j.kind == Kind::diff || j.kind == Kind::plan) {
    // A live read: its answer is what the request would have had (the diff,
    // or the plan with its plan_id), or the error.
    out["progress"] = {{"done", j.done}, {"total", j.total}, {"step", ""}};
    out["outcome"] = j.outcome.empty() ? Json(nullptr) : Json(j.outcome);
    out["message"] = j.message;
    out["exit_code"] = j.exit_code ? Json(*j.exit_code) : Json(nullptr);
    out["result"] = j.finished && !j.failed_job ? j.result : Json(nullptr);
    return out;
  }
  out["progress"] = {{"done", j.done}, {"total", j.total}, {"step", ""}};
  out["outcome"] = j.finished
                       ? Json(j.failed_job ? "failed" : (j.failed ? "some drives failed" : "done"))
                       : Json(nullptr);
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

}  // namespace lmcfg::serve::detail
