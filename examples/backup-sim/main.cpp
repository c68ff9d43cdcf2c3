// Backs up a simulated drive through the lmcfg library, as `lmcfg backup
// --port sim:STATE -o OUT` does: session, backup, write the file.
//   backup-sim STATE.json OUT.json
#include <cstdio>
#include <optional>

#include "config/config_io.hpp"
#include "db/database.hpp"
#include "link/session.hpp"
#include "ops/backup.hpp"
#include "sim/state_file.hpp"

int main(int argc, char** argv) {
  if (argc != 3) {
    std::fprintf(stderr, "usage: %s STATE.json OUT.json\n", argv[0]);
    return 2;
  }
  auto db = lmcfg::db::Database::open(LMCFG_INSTALLED_DB);
  if (!db) {
    std::fprintf(stderr, "backup-sim: %s\n", db.error().message.c_str());
    return 2;
  }
  lmcfg::link::LinkSpec link;
  // The operations know serial ports and TCP gateways; "sim:" (the in-process
  // simulated drive) is registered by the program, as the lmcfg tool does.
  lmcfg::link::register_scheme("sim", lmcfg::sim::state_file_link_factory());
  link.port = *lmcfg::link::parse_port(std::string("sim:") + argv[1]);
  auto session = lmcfg::link::open_session(link);
  if (!session) {
    std::fprintf(stderr, "backup-sim: %s\n", session.error().message.c_str());
    return 4;
  }
  auto cfg = lmcfg::ops::backup((*session)->client(), lmcfg::ops::BackupOptions{}, *db);
  if (!cfg) {
    std::fprintf(stderr, "backup-sim: backup failed: %s\n", cfg.error().message.c_str());
    return 4;
  }
  cfg->identity.link = (*session)->link_settings();
  if (auto closed = (*session)->close(); !closed) {
    std::fprintf(stderr, "backup-sim: %s\n", closed.error().message.c_str());
    return 4;
  }
  if (auto w = lmcfg::config::write_config_file(*cfg, argv[2]); !w) {
    std::fprintf(stderr, "backup-sim: %s\n", w.error().message.c_str());
    return 2;
  }
  std::size_t params = 0;
  for (const auto& layer : cfg->layers) params += layer.size();
  std::printf("backed up %zu parameters, %zu curves, %zu command table entries to %s\n", params,
              cfg->curves.size(), cfg->ct_entries.size(), argv[2]);
  return 0;
}
