#pragma once
// Undo records (docs/restore.md "Undo"): before its first write, every command
// that writes ROM or flash (restore, fleet restore, default, set --rom, undo)
// saves what it is about to change on the target as an ordinary configuration
// file, the format `lmcfg backup` writes, so `lmcfg restore`, `diff` and
// `lmcfg undo` read it. The records live per drive in the XDG state directory
// next to the recovery records (ops/recovery.hpp):
//
//   $XDG_STATE_HOME/lmcfg/undo/<drive key>/20261124T171500Z-restore.json
//
// The drive key is the recovery record's (port and MACID): LinRS reads no
// serial number. The newest kUndoKeep records of a drive are kept; older ones
// are deleted after the new one was written.
//
// What a record holds is the target's configuration in the scope the command
// writes, so that restoring it (plan against the target, leftovers back to
// their defaults) brings the drive back. Its parameters are the modified
// lists: "With this functionality the whole parameter configuration of the
// servo controller could be read out and stored in the PC/PLC" (LinRS §10.2);
// a value not listed is at its default, and restoring the record sends a
// value the command changed back to the default the target reports.
//   restore: every layer, the curves and the command table in the file's
//            scope, from the plan's own reads (Plan::target); only the data
//            blocks of curves the plan did not need to read are read now;
//   default: the layers it defaults (their modified lists, which it reads
//            anyway), every curve (--curves) and command table entry (--ct);
//   set --rom: the modified list of the parameter's layer. A one-parameter
//            file would not do: restoring it would send the layer's other
//            modified values back to their defaults as leftovers.
#include <array>
#include <chrono>
#include <filesystem>
#include <optional>
#include <string>
#include <vector>

#include "client/client.hpp"
#include "config/model.hpp"
#include "ops/restore.hpp"

namespace lmcfg::db {
class Database;
}

namespace lmcfg::ops {

inline constexpr std::size_t kUndoKeep = 10;

struct UndoOptions {
  bool enabled = false;       // the tools turn it on unless --no-undo
  std::filesystem::path dir;  // undo_dir()
  std::string port;
  std::uint8_t macid = 0;
  std::string command;  // "restore", "fleet-restore", "default", "set", "undo"
  std::size_t keep = kUndoKeep;
};

struct UndoSaved {
  std::filesystem::path path;
  std::string command;                         // what puts it back: "lmcfg undo --port P --id 0x11"
  std::vector<std::filesystem::path> removed;  // older records the rotation deleted
};

// One record in a listing.
struct UndoEntry {
  std::filesystem::path path;
  std::string drive;    // the drive key (directory name)
  std::string time;     // "2026-11-24T17:15:00Z"
  std::string command;  // the command that saved it
  std::string holds;    // "MC 12 parameters, 2 curves, 5 command table entries"
};

// <recovery_dir()>/undo.
Result<std::filesystem::path> undo_dir();

// "lmcfg undo --port P --id 0x11" (the port quoted for a shell where needed).
std::string undo_command(const std::string& port, std::uint8_t macid);

// The restore's record: the target in `scope` as the plan read it; curve data
// blocks the plan did not read (curves the restore deletes or replaces) are
// read now. Layers the plan did not read stay out of the record's scope.
Result<config::DriveConfig> undo_config_from_plan(client::Client& c, const Plan& plan,
                                                  const config::Scope& scope,
                                                  const db::Database& db);

// The record of `default`: `layers` are the modified lists it read of the
// layers it defaults (nullopt: not defaulted); the curves and the command table
// are read here when it deletes them.
Result<config::DriveConfig> undo_config_for_default(
    client::Client& c,
    const std::array<std::optional<std::vector<client::ModifiedParam>>, 4>& layers, bool curves,
    bool command_table, const db::Database& db);

// The record of `set --rom UPID`: the modified list of the UPID's layer.
Result<config::DriveConfig> undo_config_for_parameter(client::Client& c, std::uint16_t upid,
                                                      const db::Database& db);

// Writes `cfg` as a new record of o.port/o.macid (atomically), then deletes
// the oldest beyond o.keep. An error (Errc::file_error) names the path and the
// OS error and says nothing was written: the caller refuses to write.
Result<UndoSaved> save_undo(
    const UndoOptions& o, const config::DriveConfig& cfg, const db::Database& db,
    std::chrono::system_clock::time_point now = std::chrono::system_clock::now());

// Records under `dir`, newest first; `drive` (a drive_key) limits them to one
// drive. A missing directory is an empty list.
Result<std::vector<UndoEntry>> list_undo(const std::filesystem::path& dir,
                                         const std::string& drive = "");

}  // namespace lmcfg::ops
