#pragma once
// A position's approved configuration (docs/fleet.md "Approved
// configurations"): the archive revision whose <name>.json is what the
// position should hold, with who approved it, when and why. Kept in the
// archive as the ref refs/lmcfg/approved/<name>, an annotated tag object on
// that commit (tagger = who, tagger time = when, message with the trailers
// Kind:, Operator:, Reason:, Ticket:), so git keeps it with the history
// (`git cat-file tag refs/lmcfg/approved/press3/z`) and the reflog of the ref
// lists the approvals before it. Backups record every observed state as
// commits on the branch; only an approval moves this ref.
#include <cstdint>
#include <nlohmann/json.hpp>
#include <optional>
#include <string>
#include <vector>

#include "config/json_writer.hpp"
#include "fleet/archive.hpp"
#include "fleet/inventory.hpp"

namespace lmcfg::fleet {

// "refs/lmcfg/approved/<name>"
std::string approved_ref(const std::string& name);

struct Approval {
  std::string commit;     // full commit id (a revision is resolved before it is recorded)
  std::int64_t time = 0;  // seconds since the epoch (UTC)
  std::string who, reason, ticket;
  // "commissioning" (the position's first backup approved itself), "adopted"
  // (an archive from before approvals: the file it held), "operator".
  std::string kind;
};

struct ApproveRequest {
  std::string rev = "HEAD";  // any git revision; resolved to its commit id
  std::string who, reason, ticket;
  std::int64_t time = 0;          // when (seconds since the epoch)
  std::string kind = "operator";  // as Approval::kind
};

// The approval of position `d`; nullopt when it has none yet.
Result<std::optional<Approval>> read_approval(const Archive& archive, const DriveEntry& d);

// Records `req` as the approved configuration of `d`. Errors, nothing recorded:
// Errc::invalid_argument without a reason ("approving press3/z needs a reason
// ..."); Errc::not_found for a revision git does not know or one without the
// position's file.
Result<Approval> approve(Archive& archive, const DriveEntry& d, const ApproveRequest& req);

// The revision position `d` is compared with and restored from: its approved
// commit, else "HEAD" (not approved yet: an archive older than approvals).
Result<std::string> approved_rev(const Archive& archive, const DriveEntry& d);

// After a backup committed `after` (its HEAD before was `before`, "" when the
// archive had no commit): each of `drives` without an approval is approved
// once, by `who` at `time`: at `after` when its file is new there
// (commissioning: the position's first backup), else at `before` (adopted: the
// file the archive held when approvals began). The approvals made.
Result<std::vector<Approval>> commission(Archive& archive,
                                         const std::vector<const DriveEntry*>& drives,
                                         const std::string& before, const std::string& after,
                                         const std::string& who, std::int64_t time);

// {rev, time (ISO 8601 UTC), who, reason, ticket, kind}; null without an approval.
nlohmann::ordered_json approval_json(const std::optional<Approval>& a);
// The same, written as text where the writer stands.
void write_approval(config::JsonTextWriter& w, const std::optional<Approval>& a);

}  // namespace lmcfg::fleet
