// Approved configurations in the service (docs/serve.md "Approved
// configurations"): each position's status is against its approved
// configuration (fleet/approved.hpp), not the latest backup; an operator
// approves through the API (the states and their file: state_store.cpp).
#include <algorithm>

#include "serve/service_impl.hpp"

namespace lmcfg::serve {

namespace {

std::int64_t unix_seconds(TimePoint t) {
  return std::chrono::duration_cast<std::chrono::seconds>(t.time_since_epoch()).count();
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
    store.with([&](StateStore::Data& data) { data.states[d.name].approved = approval; });
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
  s.store.with([&](StateStore::Data& data) { data.states[name].approved = a; });
  // The position's status against what is approved now: a drift check of it.
  if (!s.lines.stopping()) {
    auto job = s.jobs.add(Kind::status, "drive " + name, name, [&](Job& j) { j.who = req.who; });
    if (s.enqueue(s.line_index(line), job, {name})) job_id = job->id;
  }
  s.store.save();
  Json j = fleet::approval_json(a);
  j["job"] = job_id.empty() ? Json(nullptr) : Json(job_id);
  return j;
}

void Service::Impl::note_unapproved(StateStore::Data& data, const std::string& name,
                                    const fleet::ArchivedFile& f) {
  auto& st = data.states[name];
  if (!st.approved || st.approved->commit == f.source.id) return;
  st.status = "drift";
  st.message =
      "restored from " + f.file_name +
      ", which is not the approved configuration (approved: " + st.approved->commit.substr(0, 12) +
      ")";
  // The restorer asked for it: no drift event now; the next check counts the differences.
  st.notified = "drift";
}

}  // namespace lmcfg::serve
