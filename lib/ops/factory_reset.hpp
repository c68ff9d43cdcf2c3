#pragma once
// `lmcfg default` (issue 5 §3): set chosen layers to factory defaults (seed 003
// §10.4), optionally delete all curves and command table entries, with MC
// stopped as the manual requires (§10, §11, §12), then start MC and reset so
// the defaults become active. Communication parameters of the drive (database
// flag `comm`) are written back after defaulting unless include_comm, so the
// drive still answers on the same line settings afterwards.
#include <array>
#include <string>
#include <vector>

#include "client/client.hpp"
#include "ops/backup.hpp"

namespace lmcfg::db {
class Database;
}

namespace lmcfg::ops {

struct DefaultOptions {
  std::array<bool, 4> layers{false, false, false, false};
  bool curves = false;
  bool command_table = false;
  bool include_comm = false;
  Progress progress;
};

struct DefaultReport {
  std::vector<std::string> done;  // one line per step
  // include_comm defaulted modified communication parameters: after the reset
  // the drive takes MACID and baud rate from its hex switches (seed 003 §3.2).
  bool link_may_change = false;
};

Result<DefaultReport> default_drive(client::Client& c, const DefaultOptions& opt,
                                    const db::Database* db);

}  // namespace lmcfg::ops
