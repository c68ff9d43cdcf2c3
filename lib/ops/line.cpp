#include "ops/line.hpp"

namespace lmcfg::ops {

DevicenetLinkOptions devicenet_link_for(const DevicenetLinkOptions& line, const LineDrive& d) {
  DevicenetLinkOptions l = line;
  l.master.slave_mac = d.id;
  if (d.io_modules) l.master.layout = *d.io_modules;
  return l;
}

DevicenetBackupOptions devicenet_read_for(const LineDrive& d) {
  DevicenetBackupOptions bo;
  bo.motors = d.motors;
  bo.module_values = d.module_values;
  return bo;
}

Result<std::unique_ptr<LineSession>> LineSession::open(const LineLink& line_link,
                                                       std::uint8_t first_id) {
  auto s = std::unique_ptr<LineSession>(new LineSession);
  s->link_ = line_link;
  if (line_link.is_devicenet()) return s;
  LMCFG_ASSIGN_OR_RETURN(s->linrs_, link::open_session(line_link.linrs.for_macid(first_id)));
  return s;
}

Result<config::DriveConfig> LineSession::backup(const LineDrive& d, const BackupOptions& bo,
                                                const db::Database& db) {
  if (link_.is_devicenet()) {
    DevicenetBackupOptions read = devicenet_read_for(d);
    read.progress = bo.progress;
    return capture_devicenet(devicenet_link_for(*link_.devicenet, d), read, db);
  }
  LMCFG_TRY(linrs_->relink(linrs_->line(), d.id, link_.linrs.client.checksum));
  LMCFG_ASSIGN_OR_RETURN(auto cfg, ops::backup(linrs_->client(), bo, db));
  cfg.identity.link = linrs_->link_settings();
  return cfg;
}

client::Stats LineSession::stats() const {
  return linrs_ ? linrs_->client().stats() : client::Stats{};
}

Result<void> LineSession::close() { return linrs_ ? linrs_->close() : Result<void>{}; }

}  // namespace lmcfg::ops
