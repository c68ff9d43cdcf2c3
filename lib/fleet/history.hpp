#pragma once
// A position's history from the archive (docs/fleet.md "History"): the
// commits that changed its file (fleet backups) and the empty commits that
// record a fleet restore onto it, newest first, with who and why from their
// trailers (ops/audit.hpp). `lmcfg fleet log` prints it; the service's
// GET /api/v1/drives/{name}/history returns history_json.
#include <cstdint>
#include <map>
#include <nlohmann/json.hpp>
#include <optional>
#include <string>
#include <vector>

#include "fleet/archive.hpp"
#include "fleet/inventory.hpp"

namespace lmcfg::fleet {

struct PositionEvent {
  HistoryEntry entry;
  std::string kind;    // "backup" (the file changed) or "restore" (a fleet restore's record)
  std::string who;     // the Operator: trailer, else the commit's author
  std::string reason;  // Reason: trailer, "" without one
  std::string ticket;  // Ticket: trailer, "" without one
};

// "2026-11-24T20:30:00Z" for seconds since the epoch (the times of history and approvals).
std::string iso_utc(std::int64_t seconds);

// The history of position `d`, newest first, at most `limit` entries.
Result<std::vector<PositionEvent>> position_history(const Archive& archive, const DriveEntry& d,
                                                    std::size_t limit = 100);

// When each of `drives` was last backed up with a change, as its file at
// `rev` says: the file's identity.captured_at (the time the backup that wrote
// it read the drive), in seconds since the epoch. A position without a file
// at `rev`, or whose file names no such time, is left out. One read of each
// file and none of the history, so the cost grows with the positions, not
// with the archive's age (the service's start without saved states).
Result<std::map<std::string, std::int64_t>> last_backup_times(const Archive& archive,
                                                              const std::vector<DriveEntry>& drives,
                                                              const std::string& rev = "HEAD");

// [{commit, time (ISO 8601 UTC), kind, who, reason, ticket, subject, author, message}],
// reason and ticket null when absent.
nlohmann::ordered_json history_json(const std::vector<PositionEvent>& events);

// For people: one entry per paragraph, "2026-11-24T20:30:00Z  1a2b3c4d5e6f  restore  ana"
// then the subject and "why: REASON (ticket T-17)".
std::string render_history(const std::vector<PositionEvent>& events, const std::string& name);

}  // namespace lmcfg::fleet
