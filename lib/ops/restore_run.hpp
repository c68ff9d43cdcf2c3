#pragma once
// `lmcfg restore` as one library call: plan, confirmation, execute, finding
// the drive again after --include-comm, verify. The tool only parses options,
// prints and maps the outcome to an exit code.
#include <functional>
#include <optional>

#include "link/relink.hpp"
#include "link/session.hpp"
#include "ops/confirm.hpp"
#include "ops/devicenet.hpp"
#include "ops/restore.hpp"
#include "ops/undo.hpp"

namespace lmcfg::ops {

struct RestoreRunOptions {
  RestoreOptions restore;
  bool dry_run = false;
  link::RelinkOverrides overrides;
  // Called with an accepted plan that has steps, before any write: go on or
  // decline. Unset: go on.
  std::function<Result<Consent>(const Plan&)> confirm;
  // After the confirmation, before the first write: the target's values in
  // the file's scope saved as an undo record (ops/undo.hpp). A record that
  // cannot be saved refuses the restore, nothing written.
  UndoOptions undo;
};

struct RestoreOutcome {
  enum class Stage {
    failed,           // `error` says where (plan, step, relink or verify)
    plan_refused,     // plan.problems
    dry_run,          // plan printed, nothing written
    declined,         // the user said no: nothing written
    nothing_to_do,    // the target already matches the file: nothing written
    verify_mismatch,  // written; mismatches
    restored,         // written and verified
  };
  Stage stage = Stage::failed;
  Plan plan;
  std::optional<Error> error;
  std::optional<link::RelinkReport> relink;
  std::vector<std::string> mismatches;
  bool written = false;  // execute_plan ran (some steps may have been sent)
  // The verify found a table the plan did not write differing (RAM reloaded
  // from another flash content at the reset or MC start): the second pass
  // that wrote and saved it, verified again. At most one.
  std::optional<Plan> second_pass;
  // --skip-incompatible left values out (Plan::skipped_incompatible).
  bool skipped_any() const { return !plan.skipped_incompatible.empty(); }
  std::optional<UndoSaved> undo;  // the undo record saved before the first write
  // Long steps the drive never acknowledged but after which it answered again
  // (ops/long_step.hpp), one line each ("step 9 (save ...): the drive did not
  // acknowledge ..."): `restored` then means the read-back matched anyway.
  std::vector<std::string> unacknowledged;
  // A DeviceNet controller's restore (ops/devicenet_restore.hpp): its plan;
  // `plan` stays empty (it is LinRS's). nullopt: a LinRS restore.
  std::optional<DevicenetPlan> devicenet;
  std::size_t set_commands = 0;  // a DeviceNet restore: the Set commands planned
};

RestoreOutcome run_restore(link::Session& session, const config::DriveConfig& file,
                           const db::Database& db, const RestoreRunOptions& o);

const char* stage_name(RestoreOutcome::Stage s);  // "restored and verified", ...
// stage_name, except where values were skipped: "restored except the listed
// values, verified", "nothing to do except the listed values".
std::string outcome_name(const RestoreOutcome& out);
// The error a finished restore ends with: its failure, the plan's refusal
// (every problem, "nothing written") or the read-back that differs (every
// mismatch); nullopt when it ended well (restored, nothing to do, dry run,
// declined). The service's and the ui's jobs record it.
std::optional<Error> outcome_error(const RestoreOutcome& out);

}  // namespace lmcfg::ops
