#pragma once
// Restore (issue 5 §4) in three phases.
//
// plan_restore: reads only. Checks every item of the file against the target
// drive and the database: the UPID exists on the target with the same type
// (type query 05h 04h), ROM-writable address usage (database; a UPID from a
// modified list is a ROM parameter by definition), value inside its type and
// min/max (database, else the drive's 05h 05h/06h), curve IDs, sizes and the
// curve memory limit, command table IDs and entry size. Any problem refuses
// the whole restore before a single write telegram.
//
// execute_plan: the reference algorithm of linrs-facts.md: stop MC; bring
// each restored layer to its defaults (seed 003 §10.4) unless `default_first`
// is off, in which case only differences are written and leftovers set back to
// their defaults; write ROM values; replace the command table and curves in RAM
// and save both to flash; reset so the ROM values become active (the reset
// starts MC; without a reset, start MC). With `default_first` the plan uses the
// defaulting command only when the target has leftovers and defaulting costs
// less wire time than writing those leftovers back to their defaults; otherwise
// it writes only what differs (same end state, docs/performance.md). Communication
// parameters (database flag `comm`) keep the target's own values unless
// `include_comm`. On failure the error names the step and says the drive is
// partially configured; running the same restore again converges.
//
// verify_restore: reads the target back and lists every mismatch.
#include <string>
#include <vector>

#include "client/client.hpp"
#include "config/model.hpp"
#include "ops/backup.hpp"

namespace lmcfg::db {
class Database;
}

namespace lmcfg::ops {

// The LinRS parameters that choose baud rate and MACID at start-up (seed 003
// §3.2, §10.2, §15). They count as communication parameters even without a
// database, so that --include-comm is never needed to keep a drive reachable.
inline constexpr std::uint16_t kBaudRateSource = 0x200E, kBaudRateCode = 0x2012,
                               kMacidSource = 0x206C, kMacidValue = 0x2076;
// "By Parameter" values of the two source selects (seed 003 §10.2 example).
inline constexpr std::uint32_t kBaudRateByParameter = 2, kMacidByParameter = 3;

// The database's `comm` flag, or one of the four UPIDs above.
bool is_comm_parameter(const db::Database* db, std::uint16_t upid);

struct RestoreOptions {
  bool default_first = true;         // --no-default turns it off
  bool include_comm = false;         // --include-comm
  bool reset_after = true;           // reset so ROM values become active (§9.2)
  std::uint16_t max_curve_id = 100;  // storage limit of 100 curves (facts note)
  std::size_t curve_memory = 65280;  // 70 B per curve + 4 B per setpoint (facts note)
  std::size_t ct_entry_size = 64;    // seed 003 §12.1
  Progress progress;
};

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
  };
  Action action = Action::stop_mc;
  int layer = 0;
  std::uint32_t key = 0;    // UPID, curve ID or CT entry
  std::uint32_t value = 0;  // ROM value
  std::string text;         // what a person reads in the plan
};

struct Plan {
  std::vector<std::string> problems;  // any problem refuses the restore
  std::vector<PlanStep> steps;
  std::vector<std::string> skipped;  // items deliberately not written, with why
  std::vector<std::string> notes;    // what the steps will also change (leftovers, defaults)
  // Expected state after the restore, for verify.
  config::DriveConfig expected;
  std::size_t write_telegrams = 0;  // estimate of write telegrams the steps send
  // --include-comm changes a communication parameter of the target: after the
  // reset the drive may answer only with other link settings (ops/relink.hpp).
  // The reset's own answer may then be lost; execute_plan accepts that.
  bool link_may_change = false;
  bool ok() const { return problems.empty(); }
};

Result<Plan> plan_restore(client::Client& c, const config::DriveConfig& file,
                          const db::Database* db, const RestoreOptions& opt);
std::string render_plan(const Plan& p);

Result<void> execute_plan(client::Client& c, const Plan& p, const RestoreOptions& opt);

struct VerifyReport {
  std::vector<std::string> mismatches;
  bool ok() const { return mismatches.empty(); }
};
Result<VerifyReport> verify_restore(client::Client& c, const Plan& p, const RestoreOptions& opt);

}  // namespace lmcfg::ops
