#pragma once
// The fleet inventory (docs/fleet.md): a TOML file naming the plant's lines
// (one port each, with its link settings) and the drives on each line (a
// position name, a MACID, optional labels).
//
//   [[line]]
//   name = "line1"
//   port = "/dev/ttyUSB0"
//   baud = 57600
//   [[line.drive]]
//   name = "press3/z-axis"
//   id = 0x11
//   labels = { machine = "press3" }
//
// A line whose port is a CAN link (slcan:/dev/ttyACM0, slcan:tcp://HOST:PORT,
// can0) carries DeviceNet controllers (seed 000) instead:
//
//   [[line]]
//   name = "hall1-can"
//   port = "slcan:/dev/ttyACM0"
//   can_bitrate = 250000
//   [[line.drive]]
//   name = "press5/controller"
//   devicenet_macid = 5
//   devicenet_motors = "A,B"
//
// Loading checks everything a run needs before any drive is talked to:
// unknown keys, wrong value types, names that are not archive paths,
// duplicate drive names in the plant, duplicate line names, duplicate MACIDs
// on a line. Every problem is reported as "FILE:LINE:COLUMN: what".
#include <chrono>
#include <cstdint>
#include <map>
#include <optional>
#include <string>
#include <string_view>
#include <vector>

#include "common/families.hpp"
#include "common/result.hpp"
#include "devicenet/command.hpp"
#include "fleet/names.hpp"
#include "link/spec.hpp"

namespace lmcfg::fleet {

struct Position {
  std::string file;
  int line = 0, column = 0;
  std::string str() const;  // "plant.toml:12:1"
};

struct DriveEntry {
  std::string name;        // position in the machine; the archive file is <name>.json
  std::uint8_t id = 0x11;  // LinRS: `id`; DeviceNet: `devicenet_macid` (0..63)
  std::map<std::string, std::string> labels;
  // UPIDs never compared (live or volatile values): `ignore = ["1037h"]`, with
  // the line's list added.
  std::vector<std::uint16_t> ignore;
  // lmcfg serve, a factory-fresh drive at a position the archive holds a file
  // for: "notify" (the event only) or "restore" (the archived file restored).
  // Unset: the line's, else "notify".
  std::optional<std::string> on_replaced;
  // LinRS: `family = "C1100"` (optional; common/families.hpp, docs/families.md).
  // nullptr: not named, taken for the seeds' E1100.
  const families::Family* family = nullptr;
  // DeviceNet controllers only, as --devicenet-motors, --io-modules and
  // --no-module-values: the motors (nullopt: probed), the IO modules (nullopt:
  // the default layout), whether the encoder/IO module values are read.
  std::optional<std::vector<int>> devicenet_motors;
  std::optional<devicenet::IoLayout> io_modules;
  bool module_values = true;
  Position at;
};

// Link settings as text, the way the command-line options take them (the tools
// validate them with the same code as --baud, --parity ...). Unset: the
// option's default.
struct LineEntry {
  std::string name;
  std::string port;
  std::optional<std::int64_t> baud, stop_bits, timeout_ms, retries, settle_ms, agreeing_reads;
  std::optional<std::string> parity, checksum, checksum_coverage;
  // DeviceNet lines (a CAN port): --can-bitrate, --devicenet-own-macid,
  // --devicenet-listen-ms.
  bool devicenet = false;
  std::optional<std::int64_t> can_bitrate, devicenet_own_macid, devicenet_listen_ms;
  std::vector<std::uint16_t> ignore;       // for every drive of the line
  std::optional<std::string> on_replaced;  // for every drive of the line without its own
  std::vector<DriveEntry> drives;
  Position at;
};

// [schedule] (lmcfg serve, docs/serve.md): how often the service backs up and
// checks for drift; unset = never by schedule (the API can still ask).
struct Schedule {
  std::optional<std::chrono::seconds> backup_every, status_every;
};

// [notify] (lmcfg serve): where state changes go. Empty = nowhere.
struct Notify {
  std::string webhook;  // http:// or https:// URL, POSTed a JSON object
  std::string command;  // a program run with the JSON object on stdin
};

// [archive] (lmcfg serve): a git remote every commit is pushed to (a
// configured remote's name, a URL or a path). Empty = no push.
struct ArchiveSettings {
  std::string push;
};

struct Inventory {
  std::string path;
  std::vector<LineEntry> lines;
  Schedule schedule;
  Notify notify;
  ArchiveSettings archive;
  // `require_reason = true` (top level): a write to a drive of this plant
  // (fleet restore, a restore through the service) needs a reason (--reason,
  // the API's "reason"; docs/audit.md).
  bool require_reason = false;
  std::size_t drive_count() const;
  // nullptr when no drive has that name.
  const DriveEntry* find_drive(std::string_view name, const LineEntry** line = nullptr) const;
};

// Errc::parse_error: TOML syntax; Errc::validation_failed: the rest (all
// problems, one per line of the message, each with its position).
Result<Inventory> parse_inventory(std::string_view text, std::string path);
// Errc::file_error when the file cannot be read.
Result<Inventory> load_inventory(const std::string& path);

// `lmcfg link` moved a drive to other link settings: the inventory keys that
// must change with it, spelled as the inventory spells them.
struct LinkKeys {
  std::int64_t baud = 57600;
  std::string parity = "none";
  std::int64_t stop_bits = 1;
  std::string checksum = "none";
  std::string checksum_coverage = "id";
  std::uint8_t id = 0x11;
};
struct InventoryEdit {
  std::vector<std::string> keys;      // "plant.toml:4:1: [[line]] \"press\": baud = 115200"
  std::vector<std::string> warnings;  // the other drives of a line that shares the settings
};
// Errc::not_found when no drive is called `drive`.
Result<InventoryEdit> link_inventory_edit(const Inventory& inv, std::string_view drive,
                                          const LinkKeys& after);

// A LinRS line's link specification: `base` (the tool's options) with the
// line's keys over it, checked by link::make_link_spec as the options are; a
// bad value is an error at the line's position ("FILE:L:C: line 'NAME': ...").
Result<link::LinkSpec> line_link_spec(const LineEntry& line, link::LinkInput base);
// Its checks but the port's form (check_ports reports every line's port).
Result<void> check_line_link(const LineEntry& line, link::LinkInput base);

// Whether each line's port can be reached before any drive is talked to,
// through the table of port schemes (link/port.hpp): its form ("tcp://HOST:PORT"
// has a port 1..65535), a device path ("/dev/ttyUSB0", "slcan:/dev/ttyACM0")
// exists. Registered "SCHEME:ADDRESS" ports are their scheme's to check when
// opened; a gateway that does not answer fails its line's drives at run time.
// Errc::validation_failed with every problem and its position.
Result<void> check_ports(const Inventory& inv);

// "15m", "6h", "1d", "30s": a whole number > 0 and one unit of s, m, h, d.
// Errc::invalid_argument saying what is expected.
Result<std::chrono::seconds> parse_duration(std::string_view text);

// on_replaced of the drive, else of its line, is "restore".
bool restore_when_replaced(const LineEntry& line, const DriveEntry& d);
// The UPIDs a drive's comparison skips: its own `ignore` and its line's.
std::vector<std::uint16_t> ignored_upids(const LineEntry& line, const DriveEntry& d);

// check_position_name, check_line_name: fleet/names.hpp

}  // namespace lmcfg::fleet
