#pragma once
// Restore (README) in three phases, one file each:
//
// plan_restore (restore_plan.cpp; the checks in restore_check.cpp, the tables
// in restore_tables.cpp): reads only. Compares the target with the
// file first (the target's modified list of each restored layer; a ROM read
// for a file value the target may hold as its default; the target's curves and
// command table entries), so only what differs is written. Every parameter it
// will write is checked against the target: the UPID exists with the same type
// (05h 04h, or the target's UPID list where the database lacks the address
// usage), is ROM-writable, and the value lies inside the type and the min/max
// the *target* reports (05h 05h/06h); the database supplies names, units and
// labels, and where its range disagrees with the target's the plan says so.
// Leftovers go back to the default the target reports (05h 07h). Any problem
// refuses the whole restore before a single write telegram. A value the target
// cannot take (Incompatibility) is a problem too, unless `skip_incompatible`:
// then the plan lists it in Plan::skipped_incompatible and handles it as if the
// file did not hold it.
//
// execute_plan (restore_execute.cpp): stop MC (only when something is
// written); per layer default it (§10.4) when that is cheaper than writing its
// leftovers back, then write what differs; delete / write the command table
// entries and curves that differ and save each table whose entries it writes
// or deletes to flash once; reset so
// ROM values act (or start MC when only tables changed). Communication
// parameters keep the target's values unless `include_comm`. On failure or
// interruption (Errc::interrupted) the error names the step and says the drive
// is partially configured; running the same restore again converges.
//
// verify_restore (restore_verify.cpp): reads the written scope back with
// backup's readers and lists every mismatch the comparison (ops/compare.hpp)
// finds. render_plan / plan_json (restore_render.cpp): the plan for people
// and as structured items (docs/restore.md).
#include <array>
#include <filesystem>
#include <map>
#include <nlohmann/json.hpp>
#include <string>
#include <vector>

#include "client/client.hpp"
#include "common/families.hpp"
#include "config/model.hpp"
#include "ops/backup.hpp"
#include "ops/matching.hpp"

namespace lmcfg::db {
class Database;
}

namespace lmcfg::ops {

// The LinRS parameters that choose baud rate and MACID at start-up (seed 003
// §3.2, §10.2, §15). They count as communication parameters even without a
// database, so that --include-comm is never needed to keep a drive reachable.
inline constexpr std::uint16_t kBaudRateSource = 0x200E, kBaudRateCode = 0x2012,
                               kMacidSource = 0x206C, kMacidValue = 0x2076;
// LinRS 3V27 §4.4 (p11): the checksum selection is UPID 2080h on newer
// firmware. No source gives its raw values.
inline constexpr std::uint16_t kChecksumUpid = 0x2080;
// "By Parameter" values of the two source selects (LinRS §10.2 example).
inline constexpr std::uint32_t kBaudRateByParameter = 2, kMacidByParameter = 3;

// The database's `comm` flag, or one of the four UPIDs above.
bool is_comm_parameter(const db::Database& db, std::uint16_t upid);

struct RestoreOptions {
  bool default_first = true;         // --no-default turns it off
  bool include_comm = false;         // --include-comm
  bool skip_incompatible = false;    // --skip-incompatible
  bool reset_after = true;           // reset so ROM values become active (§9.2)
  std::uint16_t max_curve_id = 100;  // storage limit of 100 curves (C1250 notes)
  std::size_t curve_memory =
      65280;  // 70 B per curve + 4 B per setpoint (public descriptions of the curve format)
  std::size_t ct_entry_size = 64;  // LinRS §12.1
  // The target's family (common/families.hpp); nullptr: the seeds' E1100.
  // C1100: curve/CT deletes and writes act on flash, no save step (LinRS 3V27
  // p32). B1100: no curve or CT group (a file with them in scope is refused)
  // and no stored defaults (layers are not defaulted first).
  const families::Family* family = nullptr;
  Progress progress;
  // Recovery record of this drive (ops/recovery.hpp; empty: none, as in
  // library use and in-process tests). execute_plan writes it before its first
  // step and deletes it after its last; plan_restore, finding one, saves the
  // tables in scope and restarts the drive even where RAM already matches.
  std::filesystem::path recovery_path;
  std::string port;  // for the record
  // Types a capture of this drive recorded (UPID -> type code, §10 05h 04h)
  // for values the database cannot type: the plan shows its writes and notes
  // by them (a SINT32 keeps its sign), as the capture does; no telegram.
  // lmcfg serve: the position's latest backup.
  std::map<std::uint16_t, std::uint8_t> known_types;
};

// Why the plan writes a ROM value (PlanStep::reason).
enum class WriteReason {
  differs,                 // the file's value differs from the target's
  leftover,                // modified on the target, not in the file: back to its default
  again_after_defaulting,  // the target held the file's value before its layer is defaulted
  kept_communication,      // the target's communication value, kept (without --include-comm)
};
// "differs", "leftover back to its default", "again after defaulting", "kept
// communication value": the plan's text and `why` in plan_json.
const char* write_reason_text(WriteReason r);

struct PlanStep {
  enum class Action {
    stop_mc,
    default_layer,
    write_rom,
    delete_all_ct,
    write_ct,
    save_ct,
    delete_all_curves,
    write_curve,
    save_curves,
    start_mc,
    reset,
    delete_ct,     // one command table entry in RAM (§12 08h 02h)
    delete_curve,  // one curve in RAM (§11 04h 02h)
  };
  Action action = Action::stop_mc;
  int layer = 0;
  std::uint32_t key = 0;    // UPID, curve ID or CT entry
  std::uint32_t value = 0;  // ROM value
  std::string text;         // what a person reads in the plan
  // write_rom: the target's value before the write (nullopt: not known) and
  // both values for people (scaled, with unit and label); `reason` says where
  // the write comes from.
  std::optional<std::uint32_t> old_value;
  std::string old_display, new_display, name;
  WriteReason reason = WriteReason::differs;
};

// Why the target cannot take a value of the file (a firmware other than the
// source's). Without skip_incompatible each one is a problem; other problems (a
// file that is not a LinRS configuration, a refused query) always refuse.
enum class Incompatibility {
  upid_absent,       // the target's firmware lacks the UPID
  type_differs,      // the target's type differs from the file's
  out_of_range,      // outside the target's min/max or its type's range
  not_rom_writable,  // the target's address usage has no ROM write bit
  curve_id_limit,    // curve ID outside 1..max_curve_id
  curve_memory,      // the curves do not fit the curve memory
  ct_entry_id,       // command table entry ID outside 0..255
  ct_entry_size,     // command table entry size differs from the target's
};
const char* reason_code(Incompatibility r);  // "upid_absent", ...

// A value of the file the target cannot take.
struct SkippedValue {
  enum class Kind { parameter, curve, ct_entry };
  Kind kind = Kind::parameter;
  int layer = 0;          // parameter: its layer
  std::uint32_t key = 0;  // UPID, curve ID or command table entry ID
  std::string name;       // from the database, the file's record or the info block
  Incompatibility reason = Incompatibility::upid_absent;
  std::string why;   // "UPID does not exist on the target (...)"
  std::string text;  // the label and `why`: the problem's message without the option
};

// What the plan read of the target before any write, kept for the undo record
// (ops/undo.hpp), so the record costs no second read of the same items.
// nullopt: not in the file's scope (or the plan stopped before reading it).
struct TargetSeen {
  struct CurveSeen {
    std::uint16_t id = 0;
    Bytes info;
    std::uint16_t data_size = 0;
    std::optional<Bytes> data;  // read only where the plan had to compare it
  };
  std::array<std::optional<std::vector<client::ModifiedParam>>, 4> layers;  // index = layer - 1
  std::optional<std::map<std::uint32_t, Bytes>> ct_entries;                 // every defined entry
  std::optional<std::vector<CurveSeen>> curves;                             // every curve found
};

struct Plan {
  std::vector<std::string> problems;  // any problem refuses the restore
  std::vector<PlanStep> steps;
  std::vector<std::string> skipped;  // items deliberately not written, with why
  // skip_incompatible: the file's values the target cannot take, not written
  // and not expected by verify (each one a problem without the option).
  std::vector<SkippedValue> skipped_incompatible;
  std::vector<std::string> notes;  // what the steps will also change (leftovers, defaults)
  // The file's values the restore leaves as the target holds them, by the rule
  // of what matches (ops/matching.hpp): a communication value the target keeps
  // (without include_comm). `item.a` the file's, `item.b` the target's. Not a
  // write, expected by verify as the target holds it, not drift afterwards.
  std::vector<KeptValue> kept;
  // Expected state after the restore, for verify.
  config::DriveConfig expected;
  std::size_t write_telegrams = 0;  // estimate of write telegrams the steps send
  // --include-comm changes a communication parameter of the target: after the
  // reset the drive may answer only with other link settings (link/relink.hpp).
  // The reset's own answer may then be lost; execute_plan accepts that.
  bool link_may_change = false;
  // What the target loses or gets replaced: command table entries and curves
  // ("curve 3 'Lift' replaced by the file's 'Lift'"), with ID and name.
  std::vector<std::string> losses;
  std::string recovered_from;  // the recovery record this plan finishes, if any
  TargetSeen target;           // the target as the plan found it (undo record)
  bool ok() const { return problems.empty(); }
  // The target already matches the file: no step, no write telegram.
  bool nothing_to_do() const { return ok() && steps.empty(); }
};

// What differs between the target two plans of the same file found ("" when
// it reads the same): each layer's modified list, the command table entries,
// the curves (info blocks and sizes, data where both read it), then the steps
// with their old values (the ROM reads behind them). A plan made earlier is
// executed only while this is "" (lmcfg serve's plan/execute).
std::string target_change(const Plan& planned, const Plan& now);

// "stop_mc", "write_rom", ...: a step's `action` in plan_json.
const char* action_name(PlanStep::Action a);

Result<Plan> plan_restore(client::Client& c, const config::DriveConfig& file,
                          const db::Database& db, const RestoreOptions& opt);
std::string render_plan(const Plan& p);
// "skipped (the target cannot take them):" and one line per skipped value;
// "" when none.
std::string render_skipped_incompatible(const Plan& p);
// The plan as structured items (docs/json-reports.md "lmcfg restore --json").
nlohmann::ordered_json plan_json(const Plan& p);

// A long step (defaulting, flash save, MC start, reset) whose answer never
// came but after which the drive answered again (ops/long_step.hpp) counts as
// sent: the steps go on, `unacknowledged` (when given) gets one line per such
// step, and the recovery record lists them and stays for the caller to remove
// once its verify has matched. Without `unacknowledged` the caller must still
// verify: execute_plan alone never proves a write.
Result<void> execute_plan(client::Client& c, const Plan& p, const RestoreOptions& opt,
                          std::vector<std::string>* unacknowledged = nullptr);

struct VerifyReport {
  std::vector<std::string> mismatches;
  bool ct_differs = false, curves_differ = false;  // a mismatch in that table
  bool ok() const { return mismatches.empty(); }
};
Result<VerifyReport> verify_restore(client::Client& c, const Plan& p, const RestoreOptions& opt);

// The second pass after a verify that found a table differing although the
// plan did not write it (the reset or MC start reloaded RAM from a flash that
// held another table, which LinRS cannot read): stop MC, write the table's
// entries that differ, save it to flash, start MC. Tables the plan `done`
// saved already are left alone (no step: nothing to do).
Result<Plan> plan_table_pass(client::Client& c, const Plan& done, const VerifyReport& v,
                             const RestoreOptions& opt);

}  // namespace lmcfg::ops
