#include "serve/service.hpp"

#include <charconv>
#include <condition_variable>
#include <ctime>
#include <deque>
#include <map>
#include <mutex>
#include <thread>

#include "common/bytes.hpp"
#include "common/layers.hpp"
#include "fleet/archive.hpp"
#include "fleet/history.hpp"

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

enum class Kind { backup, status };
const char* kind_name(Kind k) { return k == Kind::backup ? "backup" : "status"; }

double epoch_seconds(TimePoint t) {
  return std::chrono::duration<double>(t.time_since_epoch()).count();
}

struct Job {
  std::string id;
  Kind kind = Kind::backup;
  std::string scope;  // "drive NAME", "line NAME", "scheduled"
  TimePoint created;
  std::size_t total = 0, done = 0, lines_left = 0;
  std::size_t changed = 0, unchanged = 0, added = 0, failed = 0;
  std::vector<std::string> commits, errors;
  bool started = false;  // a line's worker has taken it up
  std::optional<TimePoint> finished;
};

struct Task {
  std::shared_ptr<Job> job;
  std::vector<std::string> only;  // drive names; empty = the whole line
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

  Impl(ServiceOptions o, fleet::Archive a) : opt(std::move(o)), archive(std::move(a)) {}

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
    queues[line].push_back(Task{std::move(job), std::move(only)});
    cv.notify_all();
  }

  void emit(const std::string& event, const fleet::DriveResult& r, Json details) {
    Json j{{"event", event}, {"drive", r.name}, {"line", r.line}, {"time", iso_time(opt.clock())}};
    for (auto& [k, v] : details.items()) j[k] = v;
    log("event " + event + ": " + r.name + " (line " + r.line + ")");
    if (opt.notify) opt.notify(j);
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
          const bool was_off = st.notified == "drift" || st.notified == "failed";
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
    log(std::string(kind_name(job.kind)) + " job " + job.id + ": line " + line.name + " started");
    fleet::LineRun run = fleet::read_line(line, opt.links[line_index], fo, task.only);
    std::optional<std::string> commit;
    Result<void> archived;
    {
      std::lock_guard<std::mutex> lock(archive_mu);
      archived = [&]() -> Result<void> {
        LMCFG_TRY(fleet::compare_line(line, archive, "HEAD", opt.db, run));
        if (job.kind != Kind::backup) return {};
        LMCFG_ASSIGN_OR_RETURN(auto paths, fleet::write_line(archive, opt.db, run));
        fleet::FleetRun fr;
        fr.drives = run.drives;
        LMCFG_ASSIGN_OR_RETURN(auto made, archive.commit(paths, fleet::commit_message(fr)));
        if (made) commit = made->id;
        return {};
      }();
    }
    using S = fleet::DriveResult::Status;
    std::size_t failed = 0;
    for (auto& r : run.drives) {
      // A stop asked for mid-read is not the drive's failure: no state, no event.
      if (r.error && r.error->code == Errc::interrupted) continue;
      if (!archived.ok() && r.status != S::failed) {
        r.status = S::failed;
        r.error = archived.error();
      }
      failed += r.status == S::failed;
      record(job.kind, r, commit);
    }
    std::lock_guard<std::mutex> lock(mu);
    auto& m = line_metrics[line_index];
    m.telegrams += run.stats.requests;
    m.retries += run.stats.retries;
    m.timeouts += run.stats.timeouts;
    m.errors += failed;
    ++m.runs;
    m.run_seconds += run.seconds;
    m.last_run_seconds = run.seconds;
    for (const auto& r : run.drives) {
      job.changed += r.status == S::changed;
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
  }

  void worker(std::size_t line) {
    std::unique_lock<std::mutex> lock(mu);
    for (;;) {
      cv.wait(lock, [&] { return stopping || !queues[line].empty(); });
      if (stopping) return;
      Task task = std::move(queues[line].front());
      queues[line].pop_front();
      busy[line] = true;
      task.job->started = true;
      lock.unlock();
      run_task(line, task);
      lock.lock();
      busy[line] = false;
      cv.notify_all();
    }
  }

  Json job_json(const Job& j) const {
    Json out{{"id", j.id},
             {"kind", kind_name(j.kind)},
             {"scope", j.scope},
             {"state", j.finished ? "done" : (j.started ? "running" : "queued")},
             {"created", iso_time(j.created)},
             {"finished", j.finished ? Json(iso_time(*j.finished)) : Json(nullptr)},
             {"drives", j.total},
             {"done", j.done},
             {"counts",
              {{"unchanged", j.unchanged},
               {"changed", j.changed},
               {"new", j.added},
               {"failed", j.failed}}},
             {"commits", j.commits},
             {"errors", j.errors}};
    return out;
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
  auto impl = std::make_unique<Impl>(std::move(opt), std::move(archive));
  impl->started = impl->opt.clock();
  const std::size_t n = impl->opt.inventory.lines.size();
  impl->queues.resize(n);
  impl->busy.assign(n, false);
  impl->line_metrics.resize(n);
  Impl* p = impl.get();
  for (std::size_t l = 0; l < n; ++l) impl->workers.emplace_back([p, l] { p->worker(l); });
  return std::unique_ptr<Service>(new Service(std::move(impl)));
}

Service::~Service() {
  stop();
  for (auto& w : impl_->workers) w.join();
}

void Service::stop() {
  std::lock_guard<std::mutex> lock(impl_->mu);
  impl_->stopping = true;
  impl_->cv.notify_all();
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
    auto job = s.new_job(kind, "scheduled");
    for (std::size_t l = 0; l < s.opt.inventory.lines.size(); ++l) s.enqueue(l, job, {});
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

Result<std::string> Service::backup_drive(const std::string& name) {
  const fleet::LineEntry* line = nullptr;
  if (!impl_->opt.inventory.find_drive(name, &line))
    return Error(Errc::not_found, "no drive named '" + name + "' in the inventory");
  std::lock_guard<std::mutex> lock(impl_->mu);
  if (impl_->stopping) return Error(Errc::interrupted, "the service is stopping");
  auto job = impl_->new_job(Kind::backup, "drive " + name);
  impl_->enqueue(static_cast<std::size_t>(line - impl_->opt.inventory.lines.data()), job, {name});
  impl_->log("backup job " + job->id + " asked for: drive " + name);
  return job->id;
}

Result<std::string> Service::backup_line(const std::string& name) {
  const auto& lines = impl_->opt.inventory.lines;
  for (std::size_t l = 0; l < lines.size(); ++l) {
    if (lines[l].name != name) continue;
    std::lock_guard<std::mutex> lock(impl_->mu);
    if (impl_->stopping) return Error(Errc::interrupted, "the service is stopping");
    auto job = impl_->new_job(Kind::backup, "line " + name);
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
  return o;
}

}  // namespace lmcfg::serve
