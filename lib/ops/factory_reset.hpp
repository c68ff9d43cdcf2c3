#pragma once
// `lmcfg default` (README): set chosen layers to factory defaults (seed 003
// §10.4), optionally delete all curves and command table entries, with MC
// stopped as the manual requires (§10, §11, §12), then start MC and reset so
// the defaults become active. Communication parameters of the drive (database
// flag `comm`) are written back after defaulting unless include_comm, so the
// drive still answers on the same line settings afterwards. Those values are
// stored in a recovery record (ops/recovery.hpp) before the first destructive
// step when `recovery_path` is set; a re-run finds it and writes the recorded
// values; every kept value is read back before the record is deleted.
// Interruption (ClientOptions::cancel) stops between telegrams and names the step.
#include <array>
#include <filesystem>
#include <string>
#include <vector>

#include "client/client.hpp"
#include "ops/backup.hpp"
#include "ops/undo.hpp"

namespace lmcfg::db {
class Database;
}

namespace lmcfg::ops {

struct DefaultOptions {
  std::array<bool, 4> layers{false, false, false, false};
  bool curves = false;
  bool command_table = false;
  bool include_comm = false;
  std::filesystem::path recovery_path;  // empty: no recovery record (tests, library users)
  std::string port;                     // for the record
  Progress progress;
  // Before the first write: the layers it defaults, the curves and command
  // table it deletes, saved as an undo record (ops/undo.hpp); a record that
  // cannot be saved refuses, nothing written.
  UndoOptions undo;
};

struct DefaultReport {
  std::vector<std::string> done;  // one line per step
  // include_comm defaulted modified communication parameters: after the reset
  // the drive takes MACID and baud rate from its hex switches (LinRS §3.2).
  bool link_may_change = false;
  // The communication values written back and confirmed by reading them back.
  std::vector<client::ModifiedParam> kept;
  // A record of an interrupted earlier run was found and finished.
  bool recovered = false;
  std::string recovery_note;      // what happened with the recovery record, for people
  std::optional<UndoSaved> undo;  // the undo record saved before the first write
  // Long steps the drive never acknowledged but after which it answered again
  // (ops/long_step.hpp), each read back before the run succeeds: a defaulted
  // layer lists no modified value; after the restart the saved tables are empty.
  std::vector<std::string> unacknowledged;
};

Result<DefaultReport> default_drive(client::Client& c, const DefaultOptions& opt,
                                    const db::Database& db);

}  // namespace lmcfg::ops
