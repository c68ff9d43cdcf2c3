#pragma once
// What "the drive holds the approved configuration" means (docs/fleet.md
// "What matches means"): one rule, shared by the drift check (fleet
// status, lmcfg serve), the restore plan (which values it writes and which it
// leaves), verify (what the plan expects afterwards) and the outcome a person
// reads. A value a restore keeps by policy is not a difference while the drive
// answers on its line as the inventory says; it is listed as kept, with the
// reason and what to do about it.
//
// The table (kept_by):
//   communication parameter (is_comm_parameter: 200Eh, 2012h, 206Ch, 2076h,
//   the database's `comm` flag), without --include-comm: kept, the restore
//   leaves the drive's own value so it keeps answering on its line;
//   the MACID of the identity, a DeviceNet CAN bit rate: kept, the unit's place
//   on its line, which the inventory sets;
//   everything else the diff finds: a difference.
// One exception: where the drive's own ROM selects another MACID (or baud
// rate, when the line names one) for its next restart than the inventory's
// (LinRS §15 "By Parameter"), the communication values count: after a power
// cycle it would no longer answer where the inventory says.
#include <cstdint>
#include <nlohmann/json.hpp>
#include <optional>
#include <string>
#include <vector>

#include "config/model.hpp"
#include "ops/diff.hpp"

namespace lmcfg::db {
class Database;
}

namespace lmcfg::ops {

// Why a value may stay different after a restore that ends "restored and verified".
enum class KeptBy {
  communication,  // a communication parameter: the restore keeps the drive's own value
  unit,           // the unit's place on its line (MACID, DeviceNet CAN bit rate)
};
const char* kept_by_name(KeptBy k);  // "communication", "unit": `by` in JSON
// For people: why the value stays, and what the technician can do about it.
const char* kept_reason(KeptBy k);
const char* kept_remedy(KeptBy k);

struct MatchPolicy {
  bool include_comm = false;           // the restore writes communication parameters too
  std::vector<std::uint16_t> ignored;  // never compared (the inventory's `ignore`)
  std::optional<std::uint8_t> macid;   // where the drive answers (the inventory's ID)
  std::optional<unsigned> baud;        // the line's baud rate, when it names one
};

// The table for one parameter: nullopt when a difference in it counts.
std::optional<KeptBy> kept_parameter(std::uint16_t upid, const db::Database& db, bool include_comm);
// The table for one item of a diff (approved = A, drive = B).
std::optional<KeptBy> kept_by(const DiffItem& it, const db::Database& db, const MatchPolicy& p);

struct KeptValue {
  DiffItem item;  // a: the approved configuration's value, b: the drive's
  KeptBy by = KeptBy::communication;
};

struct Matching {
  std::vector<DiffItem> differences;  // what counts: drift, a restore writes it
  std::vector<KeptValue> kept;        // what stays different by policy
  bool matches() const { return differences.empty(); }
};

// Where the drive's ROM puts it at its next restart, when that is known and
// not where the inventory says it answers: "after its next restart the drive
// answers at MACID 11h (...)", else "".
std::string moves_at_restart(const config::DriveConfig& drive, const db::Database& db,
                             const MatchPolicy& p);

// `d` (approved -> drive, as ops::diff gives it) split by the table: ignored
// UPIDs dropped, kept values apart. `drive` is the drive's side (for
// moves_at_restart).
Matching match(DiffResult d, const config::DriveConfig& drive, const db::Database& db,
               const MatchPolicy& p);

// "MC 200Eh Baud Rate Source Select: approved 2, drive 1" (`side`: what item.a
// is, "approved" or "file").
std::string kept_text(const KeptValue& k, const char* side = "approved");
// {kind, layer and upid (parameters), name, configuration (item.a), drive,
// by, reason, remedy, text}: `kept` of restore --json, fleet status --json and
// the service's positions and plans.
nlohmann::ordered_json kept_json(const KeptValue& k, const char* side = "approved");

}  // namespace lmcfg::ops
