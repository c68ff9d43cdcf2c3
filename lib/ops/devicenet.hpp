#pragma once
// Backup, restore plan, write and verify for the DeviceNet LinMot controllers
// of seed 000, over a devicenet::Master. What is read: for the controller and
// each configured motor, every Get command of §5.2 Table 5-1 that has a Set
// (devicenet::value_commands), into config::DevicenetSection::values, and the
// live values (status words, positions, IO) into `live`. These are runtime
// values: the persistent configuration is made with the vendor's PC software
// (DeviceNet §1.1), so a restore re-applies them until the next power cycle
// unless the machine's PLC keeps them (kRuntimeNote). docs/devicenet.md.
#include <array>
#include <functional>
#include <memory>
#include <optional>
#include <string>
#include <vector>

#include "can/link.hpp"
#include "config/model.hpp"
#include "devicenet/master.hpp"
#include "ops/backup.hpp"

namespace lmcfg::db {
class Database;
struct DevicenetCommand;
}  // namespace lmcfg::db

namespace lmcfg::ops {

inline constexpr const char* kRuntimeNote =
    "DeviceNet controller values are runtime values: the controller's persistent "
    "configuration is made with the vendor's PC software (seed 000 §1.1), so values written "
    "here act until the next power cycle unless the machine's PLC sets them again";

// A port names a CAN link ("can0", "vcan0", "slcan:/dev/ttyACM0").
bool is_can_port(const std::string& port);

struct DevicenetLinkOptions {
  std::string port;
  unsigned can_bitrate = 125000;
  devicenet::MasterOptions master;
  bool check_own_mac = true;   // the duplicate MAC ID check (two rounds of listening)
  can::TraceLink::Sink trace;  // frames with their DeviceNet meaning; nullptr: none
  std::string holder;          // who opens the port, recorded in its lock (slcan:)
};

// The CAN link and the connected master; releases the connection set when
// closed or destroyed (also after an interrupt).
class DevicenetSession {
 public:
  static Result<std::unique_ptr<DevicenetSession>> open(const DevicenetLinkOptions& o);
  devicenet::Master& master() { return *master_; }
  config::LinkSettings link_settings() const;
  std::uint8_t macid() const { return opt_.master.slave_mac; }
  Result<void> close();

 private:
  DevicenetLinkOptions opt_;
  std::unique_ptr<can::Link> link_;
  std::unique_ptr<devicenet::Master> master_;
};

struct DevicenetBackupOptions {
  bool live = true;  // read the informational values too
  // The motors to read; nullopt: detected by probing each of A..D (seed 000
  // does not say whether a refused probe moves the controller out of RUN;
  // the backup reports it when it does, and this avoids the probes).
  std::optional<std::vector<int>> motors;
  // Read the commands that need a master encoder or IO module (60h..6Bh);
  // without one the controller refuses each with coded error 8120h.
  bool module_values = true;
  bool reset_coded_error = false;  // a coded error pending before the backup is reset, not refused
  Progress progress;
  std::vector<std::string>* notes = nullptr;  // what was skipped and why, for people
};

// The capture `lmcfg backup --port slcan:...` writes: opens the link, reads
// the controller at l.master.slave_mac (devicenet_backup), releases it, and
// records the link in the identity (MAC ID, port, CAN bit rate, IO modules).
// A release that fails after a good read fails the capture.
Result<config::DriveConfig> capture_devicenet(const DevicenetLinkOptions& l,
                                              const DevicenetBackupOptions& opt,
                                              const db::Database& db);

// Which motors are configured (unless given): a motor the controller refuses
// with 8111h "Drive not master" (or 8110h) for Get (Rise) Curve Number, or
// does not take it (devicenet::Master::last_not_taken), is not.
// The controller's coded error pending before the backup refuses it (the
// reads could not be told from refusals) unless reset_coded_error. A
// controller that was in RUN state and is not after the reads (a refusal may
// have taken it out) is named in a note with what to do.
Result<config::DriveConfig> devicenet_backup(devicenet::Master& m,
                                             const DevicenetBackupOptions& opt,
                                             const db::Database& db);

// Display fields of every value from the database (name without "Get ",
// unit, scaled text).
void annotate_devicenet(config::DevicenetSection& s, const db::Database& db);
// A DeviceNet value for people, as diff, report and restore show it. Name:
// "motor A: Controller P (34h)" (the database's name, else the capture's,
// without "Get "; else "motor A: command 34h"; the controller's values
// "controller: ..."). Text: "2.3438 A/mm (raw 1000)" with the database's
// scale (signed where Table 5-1 gives a signed range), else the capture's
// scaled text and unit, else the raw word ("3").
std::string devicenet_value_name(const db::Database& db, const config::DevicenetValue& v);
std::string devicenet_value_text(const db::Database& db, const config::DevicenetValue& v);
// The word as a number: two's complement where Table 5-1's range is signed.
std::int64_t devicenet_word(const db::DevicenetCommand* c, std::uint16_t raw);

struct DevicenetWrite {
  int motor = config::kDevicenetController;
  std::uint8_t get = 0;  // the Set command sent is get + 1
  std::uint16_t from = 0, to = 0;
  std::string what;  // "motor A: Controller P (34h): 2.3438 A/mm (raw 1000) -> ..."
  std::string name;  // "motor A: Controller P (34h)" (devicenet_value_name)
  std::string from_display, to_display;  // "2.3438 A/mm (raw 1000)" (devicenet_value_text)
};
struct DevicenetPlan {
  std::vector<DevicenetWrite> writes;
  std::vector<std::string> problems;  // any: refused, nothing written
  std::size_t unchanged = 0;
  // What the read of the controller before the plan skipped, and why ("not
  // read: ..."); filled in by run_devicenet_restore (ops/devicenet_restore.hpp).
  std::vector<std::string> notes;
  bool refused() const { return !problems.empty(); }
};

// Compares the file's values with the controller's (a fresh backup) and the
// database's Table 5-1 ranges: a value outside its range, a motor the
// controller does not have, a command Table 5-1 cannot set are problems.
DevicenetPlan plan_devicenet_restore(const config::DriveConfig& file,
                                     const config::DriveConfig& current, const db::Database& db);
std::string render_devicenet_plan(const DevicenetPlan& p, const std::string& file_name);

// Sends each Set command (a refusal names the controller's coded error and
// stops: the values before it were written, the rest not), then reads every
// value of the file back. Mismatches are returned as text ("" = verified).
// A refused plan, or a file without DeviceNet values, is Errc::plan_refused
// and sends nothing.
Result<std::vector<std::string>> execute_devicenet_plan(devicenet::Master& m,
                                                        const DevicenetPlan& p,
                                                        const config::DriveConfig& file,
                                                        const db::Database& db,
                                                        const Progress& progress);

}  // namespace lmcfg::ops
