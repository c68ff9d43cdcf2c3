#pragma once
// A line of a plant, whichever protocol its drives speak (docs/fleet.md): a
// LinRS line (a byte link; one session for the line, switching MACID from
// drive to drive) or a CAN line of DeviceNet controllers (seed 000; one
// connection set per controller, allocated and released for each, as `lmcfg
// backup --port slcan:...` does). The fleet reads every line through this
// one call, so backup, status and `lmcfg serve` handle both.
#include <cstdint>
#include <memory>
#include <optional>
#include <vector>

#include "link/session.hpp"
#include "ops/backup.hpp"
#include "ops/devicenet.hpp"

namespace lmcfg::ops {

struct LineLink {
  LineLink() = default;
  LineLink(link::LinkSpec l) : linrs(std::move(l)) {}  // NOLINT: a LinRS line
  link::LinkSpec linrs;                                // LinRS lines
  // CAN lines: the link and the master's options; the controller's MAC ID and
  // IO modules are each drive's (devicenet_link_for).
  std::optional<DevicenetLinkOptions> devicenet;
  bool is_devicenet() const { return devicenet.has_value(); }
};

// What a line needs to know of one of its drives.
struct LineDrive {
  std::uint8_t id = 0x11;  // the LinRS MACID or the DeviceNet MAC ID
  // DeviceNet only: the controller's IO modules (nullopt: the line's layout,
  // by default seed 000's), its motors (nullopt: found by probing A..D) and
  // whether the values needing an encoder or IO module are read.
  std::optional<devicenet::IoLayout> io_modules;
  std::optional<std::vector<int>> motors;
  bool module_values = true;
};

// The line's DeviceNet options for controller `d`.
DevicenetLinkOptions devicenet_link_for(const DevicenetLinkOptions& line, const LineDrive& d);
// The DeviceNet read of controller `d` (motors, module values, live values).
DevicenetBackupOptions devicenet_read_for(const LineDrive& d);

class LineSession {
 public:
  // LinRS: opens the port, talking to `first_id`. DeviceNet: nothing is
  // opened until a drive is read.
  static Result<std::unique_ptr<LineSession>> open(const LineLink& line_link,
                                                   std::uint8_t first_id);
  // Backs up drive `d` of the line: LinRS with `bo` (ops::backup) after
  // switching to its MACID, DeviceNet as capture_devicenet. The capture's
  // identity records the link.
  Result<config::DriveConfig> backup(const LineDrive& d, const BackupOptions& bo,
                                     const db::Database& db);
  // The LinRS telegrams so far (a CAN line has none).
  client::Stats stats() const;
  // LinRS: closes the session (a simulated line saves its drives).
  Result<void> close();

 private:
  LineLink link_;
  std::unique_ptr<link::Session> linrs_;
};

}  // namespace lmcfg::ops
