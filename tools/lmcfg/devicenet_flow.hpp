#pragma once
// The DeviceNet side of backup, diff and restore (seed 000 controllers behind
// a CAN link): options to ops::DevicenetLinkOptions, the capture, and the
// restore through the flow LinRS restores take (restore_flow.hpp), with the
// same exit codes and --json report. docs/devicenet.md.
#include <string>
#include <vector>

#include "config/model.hpp"
#include "link_options.hpp"
#include "ops/devicenet.hpp"
#include "ops/restore_run.hpp"
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

// The restore flags a DeviceNet restore refuses (the LinRS-only ones), with
// the message saying why.
Result<void> check_devicenet_restore_flags(const RestoreFlags& f);

// `lmcfg restore FILE` for a DeviceNet capture; the documented exit code.
int restore_devicenet(const config::DriveConfig& file, const std::string& file_name,
                      const CommonOptions& common, const RestoreFlags& f, const db::Database& db);
// The restore on an open connection (also `lmcfg fleet restore`):
// ops::run_devicenet_restore (reads the controller, `read`: its motors and
// module values; plans; sends the Set commands; reads back) inside the
// shared flow of restore_flow.hpp (confirmation, text or --json report,
// journal, exit code); `out` says how far it went. common.port and
// common.devicenet_macid name the controller in the question. The documented
// exit code; a verified restore prints no summary (the caller does, once the
// connection is released).
int restore_devicenet_on(ops::DevicenetSession& session, const config::DriveConfig& file,
                         const std::string& file_name, const CommonOptions& common,
                         const RestoreFlags& f, ops::DevicenetBackupOptions read,
                         const db::Database& db, ops::RestoreOutcome& out);

}  // namespace lmcfg::cli
