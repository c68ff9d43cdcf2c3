#pragma once
// `lmcfg restore` of a DeviceNet controller (seed 000) as one library call, as
// ops::run_restore is for a LinRS drive: read the controller, plan,
// confirmation, the Set commands, read back. The outcome is the LinRS
// restore's (RestoreOutcome::devicenet holds the plan), so the tools confirm,
// render (text or JSON), record and map exit codes once for both protocols.
// docs/devicenet.md "Restore".
#include <atomic>
#include <functional>
#include <nlohmann/json.hpp>

#include "ops/devicenet.hpp"
#include "ops/restore_run.hpp"

namespace lmcfg::ops {

struct DevicenetRestoreRunOptions {
  DevicenetBackupOptions read;  // motors and module values (live values are never read)
  bool dry_run = false;
  // Called with an accepted plan that has Set commands, before any write: go
  // on or decline. Unset: go on.
  std::function<Result<Consent>(const DevicenetPlan&)> confirm;
  Progress progress;  // the reads, the Set commands and the read-back
  // Checked after the read and after the confirmation (a signal between two
  // polls stops the master itself): Errc::interrupted.
  const std::atomic<bool>* cancel = nullptr;
};

// Reads the controller (devicenet_backup without the live values; its notes
// go to the plan's `notes`, also when the read fails), plans
// (plan_devicenet_restore), asks, sends the Set commands and reads every
// value of the file back (execute_devicenet_plan). `written` once the first
// Set command may have gone out.
RestoreOutcome run_devicenet_restore(DevicenetSession& session, const config::DriveConfig& file,
                                     const db::Database& db, const DevicenetRestoreRunOptions& o);

// The plan in the shape of plan_json (docs/json-reports.md): `problems`,
// `nothing_to_do`, `steps` (one `devicenet_set` per Set command with `motor`,
// `command`, `name`, `old` and `new` as raw and display, `text`), `losses`,
// `skipped` and `skipped_incompatible` (always empty: a DeviceNet restore
// deletes nothing and skips nothing), `notes` (the read's, then kRuntimeNote)
// and `devicenet` (`unchanged`: the values already equal).
nlohmann::ordered_json devicenet_plan_json(const DevicenetPlan& p);

}  // namespace lmcfg::ops
