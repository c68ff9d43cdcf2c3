// The plant service's public calls (docs/serve.md): start and stop, the
// schedule, jobs asked for through the API, plans, diffs and reports. The
// line workers' jobs are in service_jobs.cpp, restores in
// service_restore.cpp, metrics and the push thread in service_metrics.cpp.
#include "serve/service.hpp"

#include <algorithm>
#include <cctype>
#include <charconv>
#include <cstdlib>
#include <ctime>
#include <random>
#ifndef _WIN32
#include <unistd.h>  // gethostname
#endif

#include "common/bytes.hpp"
#include "common/text.hpp"
#include "common/utc_time.hpp"
#include "fleet/history.hpp"
#include "ops/diff.hpp"
#include "report/report.hpp"
#include "serve/service_impl.hpp"

namespace lmcfg::serve {

std::string iso_time(TimePoint t) {
  const std::time_t s = Clock::to_time_t(t);
  const std::tm tm = utc_tm(s);
  char buf[32];
  std::strftime(buf, sizeof buf, "%Y-%m-%dT%H:%M:%SZ", &tm);
  return buf;
}

std::string detail::random_plan_id() {
  std::random_device rd;
  std::string id;
  for (int i = 0; i < 4; ++i) id += hex(rd(), 8, "");
  for (char& c : id) c = static_cast<char>(std::tolower(static_cast<unsigned char>(c)));
  return id;
}

namespace {

// `n`, or this computer's name when empty, for the archive's author;
// characters git does not take in a signature (and any but letters, digits,
// '.', '-', '_') left out.
std::string host_name(std::string n) {
  if (n.empty()) {
#ifdef _WIN32
    if (const char* c = std::getenv("COMPUTERNAME")) n = c;
#else
    char buf[256] = {};
    if (::gethostname(buf, sizeof buf - 1) == 0) n = buf;
#endif
  }
  std::erase_if(n, [](char c) {
    return !std::isalnum(static_cast<unsigned char>(c)) && c != '.' && c != '-' && c != '_';
  });
  return n.empty() ? "localhost" : n;
}

// The free text of a request, before it reaches a commit message, a job record
// or a page (common/text.hpp; docs/serve.md "Security model"): one line of
// UTF-8 without control characters, length-limited. Errc::invalid_argument
// (HTTP 400) naming the field.
Result<void> check_who(const std::string& who) { return check_line("who", who, kMaxWhoBytes); }
Result<void> check_audit(const ops::Audit& a) {
  LMCFG_TRY(check_who(a.who));
  LMCFG_TRY(check_line("reason", a.reason, kMaxReasonBytes));
  return check_line("ticket", a.ticket, kMaxTicketBytes);
}

}  // namespace

Service::Service(std::unique_ptr<Impl> impl) : impl_(std::move(impl)) {}

Result<std::unique_ptr<Service>> Service::create(ServiceOptions opt) {
  if (opt.links.size() != opt.inventory.lines.size())
    return Error(Errc::invalid_argument, "serve: one link per inventory line is needed");
  LMCFG_ASSIGN_OR_RETURN(auto archive, fleet::Archive::open(opt.archive, true));
  // A service killed during a commit (kill -9, power loss) leaves git's lock
  // files, and every later commit would fail on them. The archive is the
  // service's own (docs/serve.md): nobody else holds them now.
  LMCFG_ASSIGN_OR_RETURN(auto stale, archive.remove_stale_locks());
  const std::string host = host_name(opt.host);
  archive.set_author("lmcfg serve on " + host, "lmcfg-serve@" + host);
  for (const auto& f : stale)
    if (opt.log) opt.log("archive: removed the stale lock " + f + " (left by a stopped writer)");
  std::filesystem::path dir = opt.state_dir.empty()
                                  ? std::filesystem::path(opt.archive) / ".git" / "lmcfg-serve"
                                  : std::filesystem::path(opt.state_dir);
  auto impl = std::make_unique<Impl>(std::move(opt), std::move(archive), std::move(dir));
  Impl* p = impl.get();
  p->started = p->opt.clock();
  p->jobs.load();
  p->queue_pending();
  p->store.load(p->opt.inventory, p->archive);
  p->lines.start([p](std::size_t l, Task& t) { p->run_on_line(l, t); },
                 [p](std::deque<Task>& left) { p->drop_tasks(left); });
  if (!p->opt.inventory.archive.push.empty()) {
    Pusher::Options po;
    po.archive = p->opt.archive;
    po.remote = p->opt.inventory.archive.push;
    po.retry_first = p->opt.push_retry_first;
    po.retry_max = p->opt.push_retry_max;
    po.clock = p->opt.clock;
    po.log = [p](const std::string& s) { p->log(s); };
    po.emit = [p](const std::string& event, Json details) {
      p->emit_archive(event, std::move(details));
    };
    p->pusher = std::make_unique<Pusher>(std::move(po));
    // Commits of an earlier run that were not pushed yet (a failed push, a
    // stop or a kill before it went) go with the first push.
    auto head = p->archive.resolve("HEAD");
    p->pusher->start(head.ok() && *head);
  }
  return std::unique_ptr<Service>(new Service(std::move(impl)));
}

Service::~Service() {
  stop();
  impl_->lines.join();
  impl_->pusher.reset();  // its thread joined
}

void Service::stop() {
  impl_->lines.stop();
  impl_->jobs.stop();
  if (impl_->pusher) impl_->pusher->stop();
}

void Service::wait_idle() { impl_->lines.wait_idle(); }

void Service::tick(TimePoint now) {
  summarize(now);
  auto& s = *impl_;
  const auto& sched = s.opt.inventory.schedule;
  if (s.lines.stopping()) return;
  auto due = [&](const std::optional<std::chrono::seconds>& every, std::optional<TimePoint>& next) {
    if (!every) return false;
    if (!next) next = now;  // the first tick
    if (now < *next) return false;
    while (*next <= now) *next += *every;  // periods missed while busy are not made up
    return true;
  };
  for (Kind kind : {Kind::backup, Kind::status}) {
    {
      std::lock_guard<std::mutex> lock(s.mu);
      if (!due(kind == Kind::backup ? sched.backup_every : sched.status_every,
               kind == Kind::backup ? s.next_backup : s.next_status))
        continue;
    }
    // A line still busy with a long job (a restore) gets one waiting run of a
    // kind, not one per period missed.
    std::vector<std::size_t> lines;
    for (std::size_t l = 0; l < s.opt.inventory.lines.size(); ++l) {
      const std::size_t waiting = s.lines.queued(l, [&](const Task& t) {
        return t.job && t.job->kind == kind && t.job->scope == "scheduled";
      });
      if (waiting == 0) lines.push_back(l);
    }
    if (lines.empty()) continue;
    auto job = s.jobs.add(kind, "scheduled");
    for (std::size_t l : lines) s.enqueue(l, job, {});
    const std::size_t total = s.jobs.read(*job, [](const Job& j) { return j.total; });
    s.log(std::string("scheduled ") + kind_name(kind) + " job " + job->id + ": " +
          std::to_string(total) + " drive(s) on " + std::to_string(s.opt.inventory.lines.size()) +
          " line(s)");
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
  LMCFG_TRY(check_who(who));
  const fleet::LineEntry* line = nullptr;
  if (!impl_->opt.inventory.find_drive(name, &line))
    return Error(Errc::not_found, "no drive named '" + name + "' in the inventory");
  if (impl_->lines.stopping()) return Error(Errc::interrupted, "the service is stopping");
  auto job = impl_->jobs.add(Kind::backup, "drive " + name, name, [&](Job& j) { j.who = who; });
  if (!impl_->enqueue(impl_->line_index(line), job, {name}))
    return Error(Errc::interrupted, "the service is stopping");
  impl_->log("backup job " + job->id + " asked for: drive " + name);
  return job->id;
}

Result<std::string> Service::backup_line(const std::string& name, const std::string& who) {
  LMCFG_TRY(check_who(who));
  const auto& lines = impl_->opt.inventory.lines;
  for (std::size_t l = 0; l < lines.size(); ++l) {
    if (lines[l].name != name) continue;
    if (impl_->lines.stopping()) return Error(Errc::interrupted, "the service is stopping");
    auto job = impl_->jobs.add(Kind::backup, "line " + name, "", [&](Job& j) { j.who = who; });
    if (!impl_->enqueue(l, job, {})) return Error(Errc::interrupted, "the service is stopping");
    impl_->log("backup job " + job->id + " asked for: line " + name);
    return job->id;
  }
  return Error(Errc::not_found, "no line named '" + name + "' in the inventory");
}

Result<Json> Service::job(const std::string& id) const {
  LMCFG_ASSIGN_OR_RETURN(auto shown, impl_->jobs.show(id));
  // The failed restore waits to be run again (an automatic retry, cancellable).
  if (shown.kind == Kind::restore)
    shown.json["retry_pending"] =
        shown.failed && !shown.position.empty() && impl_->store.is_pending(shown.position);
  return shown.json;
}

Json Service::drives() const {
  Json all = Json::array();
  for (const auto& line : impl_->opt.inventory.lines)
    for (const auto& d : line.drives) all.push_back(impl_->drive_json(line, d));
  return all;
}

std::string Service::drives_text() const { return impl_->drives_text(); }

Json Service::drive_summaries() const {
  Json all = Json::array();
  for (const auto& line : impl_->opt.inventory.lines)
    for (const auto& d : line.drives) {
      Json j{{"name", d.name}, {"line", line.name}, {"id", d.id}};
      impl_->store.read([&](const detail::StateStore::Data& data) {
        const auto it = data.states.find(d.name);
        const detail::DriveState unknown;
        const detail::DriveState& st = it == data.states.end() ? unknown : it->second;
        j["status"] = st.status;
        j["last_backup"] = st.last_backup ? Json(iso_time(*st.last_backup)) : Json(nullptr);
      });
      all.push_back(std::move(j));
    }
  return all;
}

Result<Json> Service::drive(const std::string& name) const {
  const fleet::LineEntry* line = nullptr;
  const auto* d = impl_->opt.inventory.find_drive(name, &line);
  if (!d) return Error(Errc::not_found, "no drive named '" + name + "' in the inventory");
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
  LMCFG_TRY(check_line("rev", rev, kMaxRevBytes));
  LMCFG_TRY(check_who(who));
  auto& s = *impl_;
  const fleet::LineEntry* line = nullptr;
  const auto* d = s.opt.inventory.find_drive(name, &line);
  if (!d) return Error(Errc::not_found, "no drive named '" + name + "' in the inventory");
  if (line->devicenet) {
    return Error(Errc::not_supported,
                 "drive " + name + " is a DeviceNet controller on line " + line->name +
                     ": the service restores LinRS drives; use lmcfg fleet restore");
  }
  fleet::ArchivedFile file;
  std::map<std::uint16_t, std::uint8_t> known_types;
  {
    std::lock_guard<std::mutex> lock(s.archive_mu);
    // No revision named: the position's approved configuration.
    std::string from = rev;
    if (from.empty()) {
      LMCFG_ASSIGN_OR_RETURN(from, s.restore_rev(*d));
    }
    LMCFG_ASSIGN_OR_RETURN(file, fleet::load_archived(s.opt.inventory, s.archive, name, from));
    if (rev.empty() && from != "HEAD") file.rev = "approved";
    // The types the position's latest backup recorded: the plan shows the
    // drive's values by them (a SINT32 keeps its sign, as on the position).
    if (auto head = fleet::load_archived(s.opt.inventory, s.archive, name, "HEAD"); head.ok())
      for (const auto& layer : head->config.layers)
        for (const auto& p : layer)
          if (p.type) known_types[p.upid] = *p.type;
  }
  // Read on the line's worker; the same plan asked again by the same person
  // shares the read (service_live.cpp).
  const std::size_t li = s.line_index(line);
  auto f = std::make_shared<const fleet::ArchivedFile>(std::move(file));
  auto types =
      std::make_shared<const std::map<std::uint16_t, std::uint8_t>>(std::move(known_types));
  Service::Impl* p = impl_.get();
  LMCFG_ASSIGN_OR_RETURN(
      auto job,
      s.live_read(Kind::plan, li, name, "plan\n" + name + "\n" + rev + "\n" + who, who,
                  [p, li, d, f, types, who] { return p->make_plan(li, *d, *f, *types, who); }));
  return Impl::live_answer(*job);
}

Result<std::string> Service::execute(const ExecuteRequest& req) {
  LMCFG_TRY(check_audit(req.audit));
  auto& s = *impl_;
  if (s.lines.stopping()) return Error(Errc::interrupted, "the service is stopping");
  // The plan is taken and its restore job made at once (PlanStore, then
  // JobTable): of two plans of one position executed together, one runs.
  std::shared_ptr<Job> job;
  auto taken = s.plans.take(req.plan_id, [&](const StoredPlan& sp) -> Result<void> {
    if (s.opt.inventory.require_reason && req.audit.reason.empty()) {
      return Error(Errc::invalid_argument,
                   "a reason is required (the inventory sets require_reason = true): give "
                   "\"reason\"");
    }
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
    // Another technician's restore of the position, queued or running: this
    // plan was made before it wrote, and would be refused then; say who now.
    LMCFG_ASSIGN_OR_RETURN(job, s.jobs.add_restore(sp.file.drive->name, [&](Job& j) {
      j.who = req.audit.who;
      j.total = 1;
      j.step_total = sp.plan.steps.size();
    }));
    return {};
  });
  if (!taken.ok()) return taken.error();
  std::shared_ptr<StoredPlan> stored = *taken;
  Service::Impl* p = impl_.get();
  const ops::Audit audit = req.audit;
  const bool skip = req.skip_incompatible;
  if (!s.enqueue_fn(stored->line, job, [p, job, stored, audit, skip](bool run) {
        if (!run) return;
        p->run_restore_job(*job, stored->line, stored->file, audit, skip, "", &stored->plan,
                           stored->id);
      }))
    return Error(Errc::interrupted, "the service is stopping");
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

// The diff of a position's two configurations: its live and volatile values
// are never a difference (as in drift checks).
static ops::DiffResult position_diff(const Service::Impl& s, const fleet::LineEntry& line,
                                     const fleet::DriveEntry& d, const config::DriveConfig& a,
                                     const config::DriveConfig& b) {
  auto r = ops::diff(a, b, s.opt.db, nullptr, ops::DiffOptions{});
  const auto ignored = fleet::ignored_upids(line, d);
  std::erase_if(r.items, [&](const ops::DiffItem& it) {
    return it.kind == ops::DiffItem::Kind::parameter &&
           std::find(ignored.begin(), ignored.end(), it.key) != ignored.end();
  });
  return r;
}

static Result<DiffSides> diff_sides(Service::Impl& s, const std::string& name,
                                    const std::string& from, const std::string& to) {
  LMCFG_TRY(check_line("from", from, kMaxRevBytes));
  LMCFG_TRY(check_line("to", to, kMaxRevBytes));
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
    // Read on the line's worker; diffs of the position asked for meanwhile
    // share the read (service_live.cpp). The job's own answer is the diff
    // against the revision of the request that began it.
    const std::size_t li = s.line_index(line);
    auto a = std::make_shared<const fleet::ArchivedFile>(out.a);
    Service::Impl* p = &s;
    LMCFG_ASSIGN_OR_RETURN(
        auto job,
        s.live_read(
            Kind::diff, li, name, "diff\n" + name, "", [p, li, line, d, a]() -> Result<LiveAnswer> {
              fleet::FleetOptions fo;
              fo.db = p->opt.db;
              fo.backup = p->opt.backup;
              auto run = fleet::read_line(*line, p->opt.links[li], fo, {d->name});
              if (run.configs.empty() || !run.configs[0]) {
                if (!run.drives.empty() && run.drives[0].error) return *run.drives[0].error;
                return Error(Errc::io_error, "drive " + d->name + " could not be read");
              }
              LiveAnswer ans;
              ans.live = std::make_shared<const config::DriveConfig>(std::move(*run.configs[0]));
              const std::string b_name = "drive " + d->name + " (live)";
              auto r = position_diff(*p, *line, *d, a->config, *ans.live);
              ans.result = Json::parse(ops::render_json(r, a->file_name, b_name));
              return ans;
            }));
    auto answered = Service::Impl::live_answer(*job);
    if (!answered.ok()) return answered.error();
    if (!job->live) return Error(Errc::io_error, "drive " + name + " could not be read");
    out.b = *job->live;
    out.b_name = "drive " + name + " (live)";
  } else {
    LMCFG_ASSIGN_OR_RETURN(auto f, archived(to));
    out.b = std::move(f.config);
    out.b_name = f.file_name;
  }
  out.r = position_diff(s, *line, *d, out.a.config, out.b);
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
  ro.only_differences = true;  // the console's diff page opens on the differences
  return report::render_diff_report(d.a.config, d.a.file_name, d.b, d.b_name, d.r, impl_->opt.db,
                                    ro);
}

Result<std::string> Service::report_html(const std::string& name, const std::string& rev) const {
  LMCFG_TRY(check_line("rev", rev, kMaxRevBytes));
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

void Service::set_base_url(const std::string& url) {
  std::lock_guard<std::mutex> lock(impl_->mu);
  impl_->base_url = url;
}

}  // namespace lmcfg::serve
