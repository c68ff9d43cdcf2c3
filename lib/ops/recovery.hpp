#pragma once
// Recovery record (docs/restore.md): what a `default` must write back after
// defaulting a layer (the drive's communication values), stored on the host
// before the first destructive step, so that a lost write-back is never lost
// for good: a re-run of the same command finds the record, writes the recorded
// values (not the already-defaulted ones it would read now), confirms each by
// reading it back and only then deletes the record.
//
// One record per drive (port and MACID) in the XDG state directory:
// $XDG_STATE_HOME/lmcfg, else $HOME/.local/state/lmcfg; written atomically
// (temporary file, fsync, rename). Format: JSON, docs/restore.md.
#include <cstdint>
#include <filesystem>
#include <optional>
#include <string>
#include <vector>

#include "client/client.hpp"

namespace lmcfg::ops {

struct RecoveryRecord {
  std::string command;  // "default"
  std::string port;
  std::uint8_t macid = 0;
  std::string created;                      // ISO 8601 UTC
  std::vector<client::ModifiedParam> keep;  // values to write back (ROM)
  // `link`: the link options the drive was expected at after its reset ("" = none).
  std::string expect;
  // `restore`: the long steps the drive never acknowledged but after which it
  // answered again (ops/long_step.hpp); kept until the verify matched.
  std::vector<std::string> unacknowledged;
};

// The directory ($XDG_STATE_HOME/lmcfg or $HOME/.local/state/lmcfg).
Result<std::filesystem::path> recovery_dir();
// What names a drive on this host: "<port with / and : as _>-<MACID hex>h"
// (LinRS has no message that reads a serial number, LinRS §10).
std::string drive_key(const std::string& port, std::uint8_t macid);
// "<dir>/<command>-<drive_key>.json" (command "default", "link").
Result<std::filesystem::path> recovery_path(const std::string& command, const std::string& port,
                                            std::uint8_t macid);

// nullopt when there is no record; a damaged record is an error naming the file.
Result<std::optional<RecoveryRecord>> load_recovery(const std::filesystem::path& path);
Result<void> save_recovery(const std::filesystem::path& path, const RecoveryRecord& rec);
Result<void> remove_recovery(const std::filesystem::path& path);

}  // namespace lmcfg::ops
