// Live reads asked for through the API (docs/serve.md "Live reads"): a diff
// against the drive and a restore plan read the drive on the line's worker, as
// jobs of their own. The HTTP worker that asked waits a bounded time and never
// holds a lock meanwhile: a drive that does not answer keeps its line's
// worker, never the service's other clients.
#include "serve/service_impl.hpp"

namespace lmcfg::serve {

namespace {

// How long a finished live read's answer waits for the request that asked
// for it to come back: older, the drive is read again.
constexpr std::chrono::seconds kLiveAnswerKept{60};

class LineBusyCategory : public std::error_category {
 public:
  const char* name() const noexcept override { return "lmcfg-serve-line-busy"; }
  std::string message(int job) const override {
    return job ? "the line is busy: job " + std::to_string(job) + " reads the drive"
               : "the line is busy";
  }
};

Error busy_error(const std::string& message, std::uint64_t job) {
  return Error(std::error_code(static_cast<int>(job), line_busy_category()), message);
}

}  // namespace

const std::error_category& line_busy_category() noexcept {
  static const LineBusyCategory c;
  return c;
}

std::optional<LineBusy> line_busy(const Error& e) {
  if (e.code.category() != line_busy_category()) return std::nullopt;
  LineBusy b;
  if (e.code.value() > 0) b.job = std::to_string(e.code.value());
  return b;
}

Result<std::shared_ptr<Job>> Service::Impl::live_read(Kind kind, std::size_t li,
                                                      const std::string& name,
                                                      const std::string& key,
                                                      const std::string& who,
                                                      std::function<Result<LiveAnswer>()> read) {
  const auto& line = opt.inventory.lines[li];
  if (lines.stopping()) return Error(Errc::interrupted, "the service is stopping");
  // The newest job asking the same question: still to end, or ended and its
  // answer not given yet (the request that asked comes back for it). Else a
  // new one, unless the line has too many live reads queued (JobTable's lock,
  // then LineWorkers': the order in service_impl.hpp).
  const TimePoint now = opt.clock();
  LMCFG_ASSIGN_OR_RETURN(
      auto shared, jobs.share(
                       key,
                       [&](const Job& j) {
                         return !j.finished || (!j.handed && *j.finished + kLiveAnswerKept > now);
                       },
                       [&]() -> Result<void> {
                         const std::size_t queued = lines.queued(li, [](const Task& t) {
                           return t.job && (t.job->kind == Kind::diff || t.job->kind == Kind::plan);
                         });
                         if (queued < opt.live_queued) return {};
                         return busy_error("line " + line.name +
                                               " is busy: " + std::to_string(queued) +
                                               " live reads wait for it already; ask again in 2 s",
                                           0);
                       },
                       kind, name,
                       [&](Job& j) {
                         j.key = key;
                         j.who = who;
                         j.total = 1;
                       }));
  std::shared_ptr<Job> job = shared.job;
  if (shared.made) {
    Service::Impl* p = this;
    if (!enqueue_fn(li, job, [p, li, job, read = std::move(read)](bool run) {
          if (run) p->run_live(li, *job, read);
        }))
      return Error(Errc::interrupted, "the service is stopping");
    log(std::string(kind_name(kind)) + " job " + job->id + " asked for: drive " + name +
        (who.empty() ? "" : " by " + who));
  }
  // A bounded wait, by a bounded number of requests at once: the HTTP
  // server's other workers stay free for everything else.
  if (jobs.wait_finished(*job, opt.live_wait, opt.live_waiters, shared.made)) return job;
  const std::uint64_t number = std::stoull(job->id);
  return busy_error("drive " + name + ": line " + line.name + " is busy (job " + job->id +
                        " reads the drive after the work queued before it, or the drive is "
                        "slow to answer): ask again in 2 s, or see GET /api/v1/jobs/" +
                        job->id + " for its answer",
                    number);
}

void Service::Impl::run_live(std::size_t li, Job& job,
                             const std::function<Result<LiveAnswer>()>& read) {
  jobs.update(job, [](Job& j) { j.started = true; });
  std::optional<Result<LiveAnswer>> got;
  std::optional<std::string> threw;
  try {
    got.emplace(read());
  } catch (const std::exception& e) {
    threw = e.what();
  } catch (...) {
    threw = "an exception of unknown type";
  }
  if (threw) got.emplace(thrown_error(li, *threw));
  const TimePoint now = opt.clock();
  const int code = got->ok() ? 0 : (threw ? 70 : exit_code(got->error()));
  jobs.update(job, [&](Job& j) {
    if (got->ok()) {
      j.result = std::move(got->value().result);
      j.live = std::move(got->value().live);
      j.outcome = "done";
    } else {
      j.error = got->error();
      j.failed_job = true;
      j.outcome = "failed";
      j.message = j.error->message;
      j.exit_code = code;
    }
    j.done = 1;
    j.finished = now;
  });
}

Result<Json> Service::Impl::live_answer(const Job& job) {
  if (job.error) return *job.error;
  // Ended without running: the service stopped first.
  if (job.failed_job) return Error(Errc::interrupted, job.message);
  return job.result;
}

Result<LiveAnswer> Service::Impl::make_plan(
    std::size_t li, const fleet::DriveEntry& d, const fleet::ArchivedFile& f,
    const std::map<std::uint16_t, std::uint8_t>& known_types, const std::string& who) {
  const auto& line = opt.inventory.lines[li];
  StoredPlan sp;
  sp.file = f;
  sp.line = li;
  {
    // The plan of `lmcfg restore --dry-run`, the values the target cannot take
    // listed apart (execute decides whether to leave them out).
    LMCFG_ASSIGN_OR_RETURN(auto session, link::open_session(link_for(li, d)));
    ops::RestoreRunOptions ro;
    ro.restore = restore_options(line, d, true);
    ro.restore.known_types = known_types;
    ro.dry_run = true;
    auto out = ops::run_restore(*session, f.config, opt.db, ro);
    auto closed = session->close();
    if (out.stage == ops::RestoreOutcome::Stage::failed) return *out.error;
    if (!closed.ok()) return closed.error();
    sp.plan = std::move(out.plan);
  }
  sp.who = who;
  sp.id = random_plan_id();
  sp.expires = opt.clock() + opt.plan_lifetime;
  LiveAnswer a;
  a.result = plan_to_json(sp);
  log("plan " + sp.id + " for " + d.name + " <- " + sp.file.file_name + ": " +
      std::to_string(sp.plan.steps.size()) + " step(s), " +
      std::to_string(sp.plan.problems.size()) + " problem(s)" +
      (who.empty() ? "" : ", asked by " + who));
  plans.add(std::move(sp));
  return a;
}

}  // namespace lmcfg::serve
