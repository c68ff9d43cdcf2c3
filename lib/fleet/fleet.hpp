#pragma once
// Fleet operations over an inventory (docs/fleet.md): read every drive, lines
// in parallel (one worker per line: an RS485 line carries one telegram at a
// time, separate lines and gateways are independent), drives of a line in
// sequence; compare each with its archived file; back up into the archive
// (one commit per run) or report drift.
#include <functional>
#include <optional>
#include <string>
#include <vector>

#include "config/model.hpp"
#include "db/database.hpp"
#include "fleet/archive.hpp"
#include "fleet/inventory.hpp"
#include "link/session.hpp"
#include "ops/audit.hpp"
#include "ops/backup.hpp"
#include "ops/diff.hpp"
#include "ops/line.hpp"
#include "ops/matching.hpp"
#include "ops/restore_run.hpp"

namespace lmcfg::fleet {

struct DriveResult {
  enum class Status {
    unchanged,  // matches the archived file
    changed,    // differs from the archived file (backup: new file written)
    added,      // no archived file yet
    failed,     // could not be read: `error`; the archived file is kept
  };
  std::string line, name;
  std::uint8_t id = 0;
  Status status = Status::failed;
  std::optional<Error> error;
  std::size_t parameters = 0, curves = 0, ct_entries = 0;  // in the live read
  bool devicenet = false;                                  // a DeviceNet controller (a CAN line)
  std::size_t devicenet_values = 0;                        // its settable values in the live read
  ops::DiffResult diff;                                    // archived -> live
  // Compare::drift: the values that differ but are kept by policy
  // (ops/matching.hpp), not in `diff` and not a change.
  std::vector<ops::KeptValue> kept;
  double seconds = 0;
  // Differences by kind (parameter, curve, ct_entry, other).
  std::size_t count(ops::DiffItem::Kind kind) const;
};
const char* status_name(DriveResult::Status s);  // "unchanged", "changed", "new", "failed"

struct FleetOptions {
  std::vector<ops::LineLink> links;  // one per inventory line, same order
  // Names, types and decoded views; the empty database when there is none.
  std::reference_wrapper<const db::Database> db = db::Database::empty();
  ops::BackupOptions backup;  // what to read (progress and report are per drive, ignored)
  // The archive revision compared against; "" = each position's approved
  // configuration (fleet/approved.hpp; HEAD for a position not approved yet).
  std::string rev = "HEAD";
  // fleet_backup: who approves a new position's first backup (commissioning); "" = "lmcfg fleet".
  std::string who;
  // Called as each drive finishes (from the line's worker, one call at a time).
  std::function<void(const DriveResult&, std::size_t done_on_line, std::size_t on_line)> on_drive;
};

struct FleetRun {
  std::vector<DriveResult> drives;  // inventory order
  std::optional<CommitInfo> compared_to;
  bool against_approved = false;     // compared with each position's approved configuration
  std::optional<CommitInfo> commit;  // backup: the run's commit; nullopt = no changes
  double seconds = 0;
  std::size_t count(DriveResult::Status s) const;
};

// One line's part of a run: the worker body shared by fleet_backup,
// fleet_status and lmcfg serve (one worker per line, drives in sequence).
struct LineRun {
  std::vector<const DriveEntry*> entries;                   // the drives read, inventory order
  std::vector<DriveResult> drives;                          // one per entry
  std::vector<std::optional<config::DriveConfig>> configs;  // live reads; nullopt = failed
  client::Stats stats;                                      // the line session's telegrams
  double seconds = 0;
};
// Reads the drives of `line` (those named in `only`, else all) through one
// ops::LineSession opened with `link`: a LinRS line over one session, a
// DeviceNet line controller by controller. Never throws: a failure is the
// drives' error.
LineRun read_line(const LineEntry& line, const ops::LineLink& link, const FleetOptions& opt,
                  const std::vector<std::string>& only = {});
// What the line's session needs of drive `d` (its MACID; DeviceNet: motors,
// IO modules, module values).
ops::LineDrive line_drive(const DriveEntry& d);
// How a live read is compared with an archived file.
enum class Compare {
  exact,  // every difference but the ignored UPIDs: what a backup archives
  drift,  // by the rule of what matches (ops/matching.hpp, docs/fleet.md "What matches
          // means"): a value a restore keeps by policy goes to DriveResult::kept
};
// The rule's settings for drive `d`: its ignored UPIDs, the MACID and the baud
// rate (when the line names one) the inventory has it answer at.
ops::MatchPolicy match_policy(const LineEntry& line, const DriveEntry& d);
// Compares the live read of drive `d` (nullopt: its read failed) with its
// archived file at `rev`, leaving out the drive's ignored UPIDs
// (ignored_upids); sets r's diff and status (and with Compare::drift r.kept).
Result<void> compare_drive(const LineEntry& line, const DriveEntry& d, const Archive& archive,
                           const std::string& rev, const db::Database& db,
                           const std::optional<config::DriveConfig>& live, DriveResult& r,
                           Compare how = Compare::exact);
// Compares each read of `run` with its archived file at `rev` ("" = each
// drive's approved configuration) as compare_drive; sets each drive's status.
Result<void> compare_line(const LineEntry& line, const Archive& archive, const std::string& rev,
                          const db::Database& db, LineRun& run, Compare how = Compare::exact);
// Writes the files of the changed and new drives of `run` into the archive's
// work tree; returns their archive paths (to commit).
Result<std::vector<std::string>> write_line(Archive& archive, const db::Database& db,
                                            const LineRun& run);

// Backs up every drive: writes <archive>/<name>.json for new and changed ones
// (canonical JSON), keeps a failed drive's file, commits once with
// commit_message(). A run where nothing changed makes no commit. A position
// read without an approval gets one (fleet::commission: commissioning).
Result<FleetRun> fleet_backup(const Inventory& inv, Archive& archive, const FleetOptions& opt);
// Reads every drive and compares it with its file at opt.rev by the rule of
// what matches (Compare::drift); writes nothing.
Result<FleetRun> fleet_status(const Inventory& inv, const Archive& archive,
                              const FleetOptions& opt);

// "fleet backup: 1 changed, 7 unchanged, 0 new, 1 failed" and a paragraph per
// changed, new and failed drive (the changed UPIDs by name, the failure's reason).
std::string commit_message(const FleetRun& run);
// For people (status: drift per drive with the diff's wording) and scripts.
std::string render_text(const FleetRun& run, bool status);
std::string render_json(const FleetRun& run, bool status);

// The archive path of a position: "<name>.json".
// A difference by kind for messages and JSON: "2 parameters, 0 curves, 0 CT entries".
std::string counts_line(const DriveResult& r);
// One difference as the commit message says it: "MC 13A2h P Gain ...: 40 -> 1234".
std::string item_line(const ops::DiffItem& it);
std::string archive_path(const DriveEntry& d);

struct FleetRestore {
  std::string drive;         // position name
  std::string rev = "HEAD";  // "" = the position's approved configuration
  ops::LineLink link;        // the drive's line (the MACID is set from the inventory)
  ops::Audit audit;          // who and why: trailers of the recording commit
  std::reference_wrapper<const db::Database> db = db::Database::empty();
  // Runs the normal restore (plan, confirmation, verify) of the archived file
  // on the open session and returns its outcome.
  std::function<ops::RestoreOutcome(link::Session&, const config::DriveConfig&,
                                    const std::string& file_name)>
      restore;
  // DeviceNet lines: the same for a controller, on its connection (the
  // DeviceNet restore: plan against Table 5-1, confirmation, Set commands,
  // verify). RestoreOutcome::set_commands counts what it sent.
  std::function<ops::RestoreOutcome(ops::DevicenetSession&, const config::DriveConfig&,
                                    const std::string& file_name)>
      restore_devicenet;
};
struct FleetRestoreResult {
  ops::RestoreOutcome outcome;
  CommitInfo source;                 // the archive revision restored from
  std::optional<CommitInfo> record;  // the commit recording the restore (when written)
};
// A position's archived file at a revision, read and parsed: what a restore
// of that position writes (fleet restore, the service's plan).
struct ArchivedFile {
  const DriveEntry* drive = nullptr;  // in the inventory it was loaded from
  const LineEntry* line = nullptr;
  std::string rev;        // the full commit id the revision asked resolved to
  CommitInfo source;      // the commit it names
  std::string path;       // "<name>.json"
  std::string file_name;  // "<name>.json@<12 hex digits>" (messages, undo records)
  config::DriveConfig config;
};
// Errc::not_found for a drive not in the inventory, an archive without a
// commit or without the position's file at `rev`.
Result<ArchivedFile> load_archived(const Inventory& inv, const Archive& archive,
                                   const std::string& drive, const std::string& rev);
// The message of the commit recording a restore of `f`: "fleet restore: NAME
// <- NAME.json at ID12: OUTCOME" (ID12: the commit's id, 12 digits), or with a
// `cause` "fleet restore: NAME <- NAME.json at ID12 (CAUSE)" and the outcome in
// the body; the line,
// MACID, steps, skipped values, the error of a failed restore, the audit trailers.
std::string restore_record_message(const ArchivedFile& f, const ops::RestoreOutcome& outcome,
                                   const ops::Audit& audit, const std::string& cause);

// Restores position `drive`'s archived file (at rev) onto the drive now at that
// position; when anything was written, records an empty commit naming the
// position, the revision and the outcome.
Result<FleetRestoreResult> fleet_restore(const Inventory& inv, Archive& archive,
                                         const FleetRestore& opt);

}  // namespace lmcfg::fleet
