// Approved configurations in the service (docs/serve.md "Approved
// configurations"): each position's status is against its approved
// configuration (fleet/approved.hpp), not the latest backup; an operator
// approves through the API; and the states outlive a restart
// (<state_dir>/states.json).
#include <algorithm>

#include "config/atomic_file.hpp"
#include "fleet/history.hpp"
#include "serve/service_impl.hpp"

namespace lmcfg::serve {

namespace {

std::int64_t unix_seconds(TimePoint t) {
  return std::chrono::duration_cast<std::chrono::seconds>(t.time_since_epoch()).count();
}
TimePoint from_unix(std::int64_t s) { return TimePoint(std::chrono::seconds(s)); }

Json time_or_null(const std::optional<TimePoint>& t) {
  return t ? Json(unix_seconds(*t)) : Json(nullptr);
}
std::optional<TimePoint> time_of(const Json& j, const char* key) {
  if (!j.contains(key) || !j[key].is_number_integer()) return std::nullopt;
  return from_unix(j[key].get<std::int64_t>());
}

}  // namespace

Result<void> Service::Impl::compare_approved(const fleet::LineEntry& line, const Job& job,
                                             const std::string& before, fleet::LineRun& run,
                                             LineArchived& la) {
  if (job.kind == Kind::backup) {
    // Commissioning: the first backup of a position approves itself; a
    // position of an archive older than approvals adopts the file it held.
    std::vector<const fleet::DriveEntry*> read;
    for (std::size_t i = 0; i < run.entries.size(); ++i)
      if (run.configs[i] && !la.replaced[i] && !la.unfinished[i]) read.push_back(run.entries[i]);
    const std::string after = la.commit ? *la.commit : before;
    LMCFG_ASSIGN_OR_RETURN(auto made, fleet::commission(archive, read, before, after,
                                                        job.who.empty() ? "lmcfg serve" : job.who,
                                                        unix_seconds(opt.clock())));
    for (const auto& a : made) log("approved " + a.commit.substr(0, 12) + " (" + a.kind + ")");
  }
  for (std::size_t i = 0; i < run.entries.size(); ++i) {
    const auto& d = *run.entries[i];
    LMCFG_ASSIGN_OR_RETURN(auto approval, fleet::read_approval(archive, d));
    {
      std::lock_guard<std::mutex> lock(mu);
      states[d.name].approved = approval;
    }
    if (!run.configs[i]) continue;
    fleet::DriveResult r = run.drives[i];
    // The one meaning of "matches" (ops/matching.hpp): kept values are not drift.
    LMCFG_TRY(fleet::compare_drive(line, d, archive, approval ? approval->commit : "HEAD", opt.db,
                                   run.configs[i], r, fleet::Compare::drift));
    la.against[i] = std::move(r);
  }
  return {};
}

Result<std::string> Service::Impl::restore_rev(const fleet::DriveEntry& d) const {
  return fleet::approved_rev(archive, d);
}

Result<Json> Service::approve(const std::string& name, const ApproveRequest& req) {
  auto& s = *impl_;
  const fleet::LineEntry* line = nullptr;
  const auto* d = s.opt.inventory.find_drive(name, &line);
  if (!d) return Error(Errc::not_found, "no drive named '" + name + "' in the inventory");
  fleet::ApproveRequest ar;
  ar.rev = req.rev.empty() ? "HEAD" : req.rev;
  ar.who = req.who;
  ar.reason = req.reason;
  ar.ticket = req.ticket;
  ar.time = unix_seconds(s.opt.clock());
  fleet::Approval a;
  {
    std::lock_guard<std::mutex> lock(s.archive_mu);
    LMCFG_ASSIGN_OR_RETURN(a, fleet::approve(s.archive, *d, ar));
  }
  s.log("approved " + name + " <- " + fleet::archive_path(*d) + " at " + a.commit.substr(0, 12) +
        " by " + a.who + ": " + a.reason);
  std::string job_id;
  {
    std::lock_guard<std::mutex> lock(s.mu);
    s.states[name].approved = a;
    // The position's status against what is approved now: a drift check of it.
    if (!s.stopping) {
      auto job = s.new_drive_job(Kind::status, name);
      job->who = req.who;
      s.enqueue(s.line_index(line), job, {name});
      job_id = job->id;
    }
  }
  s.save_states();
  Json j = fleet::approval_json(a);
  j["job"] = job_id.empty() ? Json(nullptr) : Json(job_id);
  return j;
}

void Service::Impl::note_unapproved(const std::string& name, const fleet::ArchivedFile& f) {
  auto& st = states[name];
  if (!st.approved || st.approved->commit == f.source.id) return;
  st.status = "drift";
  st.message =
      "restored from " + f.file_name +
      ", which is not the approved configuration (approved: " + st.approved->commit.substr(0, 12) +
      ")";
  // The restorer asked for it: no drift event now; the next check counts the differences.
  st.notified = "drift";
}

void Service::Impl::save_states() {
  // The file's writers in turn, each with the states as they are then (the
  // last write holds the newest).
  std::lock_guard<std::mutex> file_lock(states_file_mu);
  Json all = Json::object();
  {
    std::lock_guard<std::mutex> lock(mu);
    for (const auto& [name, st] : states) {
      all[name] = {{"status", st.status},
                   {"message", st.message},
                   {"last_backup", time_or_null(st.last_backup)},
                   {"last_attempt", time_or_null(st.last_attempt)},
                   {"last_kind", st.last_kind},
                   {"last_ok", st.last_ok},
                   {"last_exit_code", st.last_exit_code},
                   {"differences", st.differences},
                   {"differing", st.differing},
                   {"notified", st.notified},
                   {"drive_state", st.drive_state},
                   {"kept", st.kept}};
    }
  }
  std::error_code ec;
  std::filesystem::create_directories(state_dir, ec);
  const Json file{{"format", "lmcfg-serve-states"}, {"version", 1}, {"drives", all}};
  // Written after each run; a failure costs the states after a restart, not the run.
  if (auto w = config::write_file_atomic(state_dir / "states.json", file.dump(1) + "\n"); !w.ok())
    log("states: " + w.error().message);
}

void Service::Impl::load_states() {
  const auto path = state_dir / "states.json";
  std::error_code ec;
  Json drives;
  if (std::filesystem::exists(path, ec)) {
    auto text = config::read_text_file(path, 1 << 24);
    Json j = text.ok() ? Json::parse(*text, nullptr, false) : Json();
    if (j.is_object() && j.contains("drives") && j["drives"].is_object())
      drives = j["drives"];
    else
      log("states: " + path.string() + " is not a states file of lmcfg serve; states start empty");
  }
  for (const auto& line : opt.inventory.lines) {
    for (const auto& d : line.drives) {
      auto& st = states[d.name];
      if (auto a = fleet::read_approval(archive, d); a.ok()) st.approved = *a;
      if (drives.is_object() && drives.contains(d.name) && drives[d.name].is_object()) {
        const Json& j = drives[d.name];
        st.status = j.value("status", st.status);
        st.message = j.value("message", st.message);
        st.last_backup = time_of(j, "last_backup");
        st.last_attempt = time_of(j, "last_attempt");
        st.last_kind = j.value("last_kind", "");
        st.last_ok = j.value("last_ok", false);
        st.last_exit_code = j.value("last_exit_code", 0);
        st.differences = j.value("differences", std::size_t{0});
        if (j.contains("differing") && j["differing"].is_array())
          for (const auto& t : j["differing"])
            if (t.is_string()) st.differing.push_back(t.get<std::string>());
        st.notified = j.value("notified", "");
        if (j.contains("kept") && j["kept"].is_array()) st.kept = j["kept"];
        if (j.contains("drive_state") && j["drive_state"].is_string())
          st.drive_state = j["drive_state"].get<std::string>();
        continue;
      }
      // No state saved (a first start, or one before states were kept): the
      // last backup that changed the position's file, from the archive.
      auto events = fleet::position_history(archive, d, 20);
      if (!events.ok()) continue;
      for (const auto& ev : *events) {
        if (ev.kind != "backup") continue;
        st.last_backup = from_unix(ev.entry.time);
        st.message = "not read since the service started";
        break;
      }
    }
  }
}

}  // namespace lmcfg::serve
