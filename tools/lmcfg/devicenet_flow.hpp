#pragma once
// The DeviceNet side of backup, diff and restore (seed 000 controllers behind
// a CAN link): options to ops::DevicenetLinkOptions, the capture, and the
// restore flow (plan, confirmation, Set commands, verification) with the same
// exit codes as on LinRS. docs/devicenet.md.
#include <string>
#include <vector>

#include "config/model.hpp"
#include "link_options.hpp"
#include "ops/devicenet.hpp"
#include "restore_flow.hpp"

namespace lmcfg::cli {

Result<ops::DevicenetLinkOptions> devicenet_link_options(const CommonOptions& o);
// --devicenet-motors and --no-module-values into the backup's options.
Result<ops::DevicenetBackupOptions> devicenet_read_options(const CommonOptions& o);

struct DevicenetCapture {
  bool live = true;
  bool reset_coded_error = false;
};
// Opens the link, reads the controller, releases it. Notes (skipped reads)
// are printed on stderr unless --quiet.
Result<config::DriveConfig> devicenet_capture(const CommonOptions& o, const db::Database& db,
                                              const DevicenetCapture& c);

// `lmcfg restore FILE` for a DeviceNet capture; the documented exit code.
int restore_devicenet(const config::DriveConfig& file, const std::string& file_name,
                      const CommonOptions& common, const RestoreFlags& f, const db::Database& db);

}  // namespace lmcfg::cli
