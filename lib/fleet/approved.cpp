#include "fleet/approved.hpp"

#include "common/text.hpp"
#include "fleet/fleet.hpp"
#include "fleet/history.hpp"
#include "ops/audit.hpp"

namespace lmcfg::fleet {

std::string approved_ref(const std::string& name) { return "refs/lmcfg/approved/" + name; }

Result<std::optional<Approval>> read_approval(const Archive& archive, const DriveEntry& d) {
  LMCFG_ASSIGN_OR_RETURN(auto tag, archive.tag_ref(approved_ref(d.name)));
  if (!tag) return std::optional<Approval>();
  Approval a;
  a.commit = tag->commit;
  a.time = tag->time;
  a.who = tag->tagger;
  for (const auto& [key, value] : message_trailers(tag->message)) {
    if (key == "Operator") a.who = value;
    if (key == "Reason") a.reason = value;
    if (key == "Ticket") a.ticket = value;
    if (key == "Kind") a.kind = value;
  }
  return std::optional<Approval>(std::move(a));
}

Result<Approval> approve(Archive& archive, const DriveEntry& d, const ApproveRequest& req) {
  // The text rules of every free text that reaches a commit message
  // (common/text.hpp), as for a restore's reason and ticket: one line of
  // UTF-8 without control characters (a line break would forge a trailer).
  if (req.kind == "operator") LMCFG_TRY(check_line("who", req.who, kMaxWhoBytes));
  LMCFG_TRY(check_line("reason", req.reason, kMaxReasonBytes));
  LMCFG_TRY(check_line("ticket", req.ticket, kMaxTicketBytes));
  LMCFG_TRY(check_line("rev", req.rev, kMaxRevBytes));
  // Who changed what the position should hold, and why, is the record's point.
  if (req.reason.empty())
    return Error(Errc::invalid_argument,
                 "approving " + d.name +
                     " needs a reason (why this configuration is the one the position should "
                     "hold); nothing recorded");
  const std::string rev = req.rev.empty() ? "HEAD" : req.rev;
  LMCFG_ASSIGN_OR_RETURN(auto commit, archive.resolve(rev));
  if (!commit) return Error(Errc::not_found, "archive " + archive.dir() + " has no commit yet");
  LMCFG_ASSIGN_OR_RETURN(auto file, archive.read(archive_path(d), commit->id));
  if (!file)
    return Error(Errc::not_found, "archive " + archive.dir() + " has no " + archive_path(d) +
                                      " at " + rev + " (" + commit->id.substr(0, 12) +
                                      "): nothing to approve; nothing recorded");
  Approval a{commit->id, req.time, req.who, req.reason, req.ticket, req.kind};
  std::string message = "lmcfg approve: " + d.name + " <- " + archive_path(d) + " at " +
                        commit->id.substr(0, 12) + " (" + rev + ")\n\nKind: " + req.kind + "\n" +
                        ops::trailers(ops::Audit{req.who, req.reason, req.ticket});
  LMCFG_TRY(archive.set_tag_ref(approved_ref(d.name), commit->id, req.who, req.time, message));
  return a;
}

Result<std::string> approved_rev(const Archive& archive, const DriveEntry& d) {
  LMCFG_ASSIGN_OR_RETURN(auto a, read_approval(archive, d));
  return a ? a->commit : std::string("HEAD");
}

Result<std::vector<Approval>> commission(Archive& archive,
                                         const std::vector<const DriveEntry*>& drives,
                                         const std::string& before, const std::string& after,
                                         const std::string& who, std::int64_t time) {
  std::vector<Approval> made;
  for (const DriveEntry* d : drives) {
    LMCFG_ASSIGN_OR_RETURN(auto existing, read_approval(archive, *d));
    if (existing) continue;
    std::optional<std::string> earlier;
    if (!before.empty()) {
      LMCFG_ASSIGN_OR_RETURN(earlier, archive.read(archive_path(*d), before));
    }
    ApproveRequest req;
    req.who = who;
    req.time = time;
    if (earlier) {
      req.rev = before;
      req.kind = "adopted";
      req.reason = "the file the archive held when approvals began (no approval recorded before)";
    } else {
      req.rev = after;
      req.kind = "commissioning";
      req.reason = "commissioning: the position's first backup";
    }
    auto a = approve(archive, *d, req);
    // A position whose file is not at `after` (its read failed) waits for its first backup.
    if (!a.ok() && a.error().code == Errc::not_found) continue;
    if (!a.ok()) return a.error();
    made.push_back(std::move(a).value());
  }
  return made;
}

namespace {

template <class W>
void write_approval_to(W& w, const std::optional<Approval>& a) {
  if (!a) {
    w.value(nullptr);
    return;
  }
  w.begin_object();
  w.member("rev", a->commit);
  w.member("time", iso_utc(a->time));
  w.member("who", a->who);
  w.member_or_null("reason", a->reason);
  w.member_or_null("ticket", a->ticket);
  w.member("kind", a->kind);
  w.end_object();
}

}  // namespace

nlohmann::ordered_json approval_json(const std::optional<Approval>& a) {
  config::JsonBuilder b;
  write_approval_to(b, a);
  return b.take();
}

void write_approval(config::JsonTextWriter& w, const std::optional<Approval>& a) {
  write_approval_to(w, a);
}

}  // namespace lmcfg::fleet
