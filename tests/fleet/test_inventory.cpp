// The fleet inventory (lib/fleet/inventory, docs/fleet.md): the form scripts
// write, and every kind of bad inventory with its exact message and position.
#include <catch2/catch.hpp>

#include "devicenet/catalogue.hpp"
#include "files.hpp"
#include "fleet/inventory.hpp"

// This file's own namespace: the test binary is a unity build (tests/CMakeLists.txt).
namespace fleet_test_inventory {

using namespace lmcfg;

namespace {

std::string problems(const std::string& text) {
  auto inv = fleet::parse_inventory(text, "plant.toml");
  REQUIRE_FALSE(inv.ok());
  return inv.error().message;
}

}  // namespace

TEST_CASE("fleet inventory: the form of docs/fleet.md loads with its settings and labels",
          "[fleet][inventory]") {
  const std::string text = R"([[line]]
name = "line1"
port = "/dev/ttyUSB0"
baud = 57600            # parity, stop_bits, checksum, timeout_ms as the CLI options
[[line.drive]]
name = "press3/z-axis"
id = 0x11
labels = { machine = "press3" }

[[line]]
name = "gateway-2"
port = "tcp://10.0.0.5:4001"
parity = "even"
checksum = "crc"
timeout_ms = 300
[[line.drive]]
name = "press4/x"
id = 17
[[line.drive]]
name = "press4/y"
id = 0x12
)";
  auto inv = fleet::parse_inventory(text, "plant.toml");
  REQUIRE(inv.ok());
  REQUIRE(inv->lines.size() == 2);
  const auto& l1 = inv->lines[0];
  CHECK(l1.name == "line1");
  CHECK(l1.port == "/dev/ttyUSB0");
  CHECK(l1.baud == 57600);
  CHECK_FALSE(l1.parity);
  REQUIRE(l1.drives.size() == 1);
  CHECK(l1.drives[0].name == "press3/z-axis");
  CHECK(l1.drives[0].id == 0x11);
  CHECK(l1.drives[0].labels == std::map<std::string, std::string>{{"machine", "press3"}});
  CHECK(l1.drives[0].at.str() == "plant.toml:5:1");
  const auto& l2 = inv->lines[1];
  CHECK(l2.parity == "even");
  CHECK(l2.checksum == "crc");
  CHECK(l2.timeout_ms == 300);
  CHECK(l2.drives[0].id == 17);
  CHECK(inv->drive_count() == 3);
  const fleet::LineEntry* line = nullptr;
  REQUIRE(inv->find_drive("press4/y", &line));
  CHECK(line == &l2);
  CHECK(inv->find_drive("press4/z") == nullptr);
}

TEST_CASE("fleet inventory: TOML syntax errors name file, line and column", "[fleet][inventory]") {
  auto inv = fleet::parse_inventory("[[line]]\nname = \"a\nport = 1\n", "plant.toml");
  REQUIRE_FALSE(inv.ok());
  CHECK(inv.error().code == make_error_code(Errc::parse_error));
  CHECK(inv.error().message.rfind("plant.toml:2:", 0) == 0);
}

TEST_CASE("fleet inventory: unknown keys, wrong types and bad names are all reported",
          "[fleet][inventory]") {
  CHECK(problems(R"([[line]]
name = "l1"
port = "/dev/ttyUSB0"
baudrate = 57600
[[line.drive]]
name = "a/../b"
id = 300
colour = "red"
[[line.drive]]
name = "c"
labels = { machine = 3 }
)") == "plant.toml:4:1: unknown key 'baudrate' in line 'l1' (known: name, port, baud, parity, "
       "stop_bits, checksum, checksum_coverage, timeout_ms, retries, settle_ms, agreeing_reads, "
       "ignore, on_replaced, drive)\n"
       "plant.toml:8:1: unknown key 'colour' in drive of line 'l1' (known: name, id, labels, "
       "ignore, on_replaced, family)\n"
       "plant.toml:6:8: drive name 'a/../b' must be path segments separated by '/', none "
       "empty, '.' or '..'\n"
       "plant.toml:7:6: drive 'a/../b': id 300 is not a MACID 0..255\n"
       "plant.toml:9:1: drive 'c' has no 'id' (its MACID, e.g. id = 0x11)\n"
       "plant.toml:11:22: label 'machine' must be a string");
  CHECK(problems("[[line]]\nname = \"l1\"\nport = 5\n[[line.drive]]\nname = \"x y\"\nid = 1\n") ==
        "plant.toml:3:8: 'port' must be a string\n"
        "plant.toml:5:8: drive name 'x y' contains ' ' (allowed: letters, digits, . _ - and /)");
  CHECK(problems("title = \"plant\"\n") == "plant.toml:1:1: the inventory has no lines ([[line]])");
  CHECK(problems("[[line]]\nname = \"l1\"\nport = \"/dev/null\"\n") ==
        "plant.toml:1:1: line 'l1' has no drives ([[line.drive]])");
}

TEST_CASE("fleet inventory: duplicate names and duplicate MACIDs on a line are refused",
          "[fleet][inventory]") {
  CHECK(problems(R"([[line]]
name = "l1"
port = "/dev/ttyUSB0"
[[line.drive]]
name = "press3/z"
id = 0x11
[[line.drive]]
name = "press3/x"
id = 0x11
[[line]]
name = "l1"
port = "/dev/ttyUSB1"
[[line.drive]]
name = "press3/z"
id = 0x11
)") == "plant.toml:7:1: line 'l1': drives 'press3/z' (plant.toml:4:1) and 'press3/x' "
       "(plant.toml:7:1) both have MACID 11h\n"
       "plant.toml:10:1: duplicate line name 'l1' (first at plant.toml:1:1)\n"
       "plant.toml:13:1: duplicate drive name 'press3/z' at plant.toml:13:1 (first at "
       "plant.toml:4:1)");
}

TEST_CASE("fleet inventory: names that do not fit the archive, labels with control characters",
          "[fleet][inventory][names]") {
  CHECK(problems(R"([[line]]
name = "l1\nOperator: x"
port = "/dev/ttyUSB0"
[[line.drive]]
name = ".git/hooks/pre-commit"
id = 0x11
[[line.drive]]
name = "press3/z"
id = 0x12
labels = { note = "a\u0007b" }
)") == "plant.toml:2:8: line name contains a control character (0x0A at offset 2): give one "
       "line without control characters\n"
       "plant.toml:5:8: drive name '.git/hooks/pre-commit' has a '.git' segment: that is git's "
       "own folder in the archive; rename the drive\n"
       "plant.toml:10:19: label 'note' contains a control character (0x07 at offset 1): give "
       "one line without control characters");
  CHECK(problems("[[line]]\nname = \"a\\\\b\"\nport = \"/dev/null\"\n[[line.drive]]\nname = "
                 "\"x\"\nid = 1\n") ==
        "plant.toml:2:8: line name 'a\\b' contains '\\': use '/' or another character");
  // A trailing dot or space: another file, or git's folder, on Windows.
  CHECK(problems(R"([[line]]
name = "press3 /z"
port = "/dev/ttyUSB0"
[[line.drive]]
name = "p/.git."
id = 0x11
)") == "plant.toml:2:8: line name 'press3 /z' has the segment 'press3 ', which ends in a space: "
       "Windows drops a trailing dot or space from a file or folder name (there it is "
       "'press3'); rename the line\n"
       "plant.toml:5:8: drive name 'p/.git.' has the segment '.git.', which ends in a dot: "
       "Windows drops a trailing dot or space from a file or folder name (there it is '.git'); "
       "rename the drive");
}

TEST_CASE("fleet inventory: drive or line names that differ only in case are refused",
          "[fleet][inventory][names]") {
  // One file on a case-insensitive file system (a clone of the archive on
  // macOS or Windows): press3/Z.json and press3/z.json.
  CHECK(problems(R"([[line]]
name = "L2"
port = "/dev/ttyUSB0"
[[line.drive]]
name = "press3/Z"
id = 0x12
[[line.drive]]
name = "press3/z"
id = 0x13
[[line]]
name = "l2"
port = "/dev/ttyUSB1"
[[line.drive]]
name = "y"
id = 1
)") == "plant.toml:7:1: drive names 'press3/Z' (plant.toml:4:1) and 'press3/z' differ only in "
       "case: one file on a case-insensitive file system; rename one\n"
       "plant.toml:10:1: line names 'L2' (plant.toml:1:1) and 'l2' differ only in case: "
       "rename one");
}

TEST_CASE("fleet inventory: ports that cannot be reached are found before any drive is read",
          "[fleet][inventory]") {
  auto inv = fleet::parse_inventory(R"([[line]]
name = "usb"
port = "/dev/no-such-adapter"
[[line.drive]]
name = "a"
id = 1
[[line]]
name = "gw"
port = "tcp://10.0.0.5"
[[line.drive]]
name = "b"
id = 1
[[line]]
name = "ok"
port = "tcp://10.0.0.5:4001"
[[line.drive]]
name = "c"
id = 1
)",
                                    "plant.toml");
  REQUIRE(inv.ok());
  auto ports = fleet::check_ports(*inv);
  REQUIRE_FALSE(ports.ok());
  CHECK(ports.error().message ==
        "plant.toml:1:1: line 'usb': port /dev/no-such-adapter does not exist (is the adapter "
        "plugged in?)\n"
        "plant.toml:7:1: line 'gw': port 'tcp://10.0.0.5' is not tcp://HOST:PORT with PORT "
        "1..65535");
}

TEST_CASE("fleet inventory: a file that cannot be read says so", "[fleet][inventory]") {
  auto inv = fleet::load_inventory("/no/such/plant.toml");
  REQUIRE_FALSE(inv.ok());
  CHECK(inv.error().message == "/no/such/plant.toml: cannot open the inventory");
}

TEST_CASE("fleet inventory: require_reason is a top-level true or false", "[fleet][inventory]") {
  const std::string lines =
      "[[line]]\nname = \"l\"\nport = \"/dev/ttyUSB0\"\n"
      "[[line.drive]]\nname = \"a\"\nid = 0x11\n";
  auto on = fleet::parse_inventory("require_reason = true\n" + lines, "plant.toml");
  REQUIRE(on.ok());
  CHECK(on->require_reason);
  auto off = fleet::parse_inventory(lines, "plant.toml");
  REQUIRE(off.ok());
  CHECK_FALSE(off->require_reason);
  CHECK(problems("require_reason = \"yes\"\n" + lines) ==
        "plant.toml:1:18: 'require_reason' must be true or false");
  // Below a table header the key belongs to that table, which knows no such key.
  CHECK(problems(lines + "require_reason = true\n") ==
        "plant.toml:7:1: unknown key 'require_reason' in drive of line 'l' (known: name, id, "
        "labels, ignore, on_replaced, family)");
}

TEST_CASE("fleet inventory: a CAN port's line holds DeviceNet controllers with their settings",
          "[fleet][inventory][devicenet]") {
  const std::string text = R"([[line]]
name = "hall1-can"
port = "slcan:/dev/ttyACM0"
can_bitrate = 250000
devicenet_own_macid = 60
devicenet_listen_ms = 200
timeout_ms = 150
[[line.drive]]
name = "press5/controller"
devicenet_macid = 5
devicenet_motors = "A,B"
no_module_values = true
io_modules = "control-in,addressed-in,status-out,addressed-out"
labels = { machine = "press5" }
[[line.drive]]
name = "press6/controller"
devicenet_macid = 0x3F

[[line]]
name = "gateway-can"
port = "slcan:tcp://10.0.0.7:4002"
[[line.drive]]
name = "press7/controller"
devicenet_macid = 5

[[line]]
name = "socketcan"
port = "can0"
[[line.drive]]
name = "press8/controller"
devicenet_macid = 1
)";
  auto inv = fleet::parse_inventory(text, "plant.toml");
  INFO((inv.ok() ? std::string() : inv.error().message));
  REQUIRE(inv.ok());
  REQUIRE(inv->lines.size() == 3);
  const auto& can = inv->lines[0];
  CHECK(can.devicenet);
  CHECK(can.can_bitrate == 250000);
  CHECK(can.devicenet_own_macid == 60);
  CHECK(can.devicenet_listen_ms == 200);
  CHECK(can.timeout_ms == 150);
  REQUIRE(can.drives.size() == 2);
  CHECK(can.drives[0].id == 5);
  CHECK(can.drives[0].devicenet_motors == std::vector<int>{0, 1});
  CHECK_FALSE(can.drives[0].module_values);
  REQUIRE(can.drives[0].io_modules);
  CHECK(devicenet::module_names(*can.drives[0].io_modules) ==
        std::vector<std::string>{"control-in", "addressed-in", "status-out", "addressed-out"});
  CHECK(can.drives[0].labels == std::map<std::string, std::string>{{"machine", "press5"}});
  CHECK(can.drives[1].id == 0x3F);
  CHECK_FALSE(can.drives[1].devicenet_motors);
  CHECK_FALSE(can.drives[1].io_modules);
  CHECK(can.drives[1].module_values);
  CHECK(inv->lines[1].devicenet);
  CHECK(inv->lines[2].devicenet);
  CHECK(inv->lines[2].drives[0].id == 1);
  // The line's port is its protocol: a LinRS line of docs/fleet.md is not one.
  auto linrs = fleet::parse_inventory(
      "[[line]]\nname = \"l\"\nport = \"/dev/ttyUSB0\"\n[[line.drive]]\nname = \"a\"\nid = 1\n",
      "plant.toml");
  REQUIRE(linrs.ok());
  CHECK_FALSE(linrs->lines[0].devicenet);
}

TEST_CASE(
    "fleet inventory: LinRS keys on a DeviceNet line and DeviceNet keys on a LinRS line are "
    "errors at their position",
    "[fleet][inventory][devicenet]") {
  CHECK(problems(R"([[line]]
name = "can1"
port = "slcan:/dev/ttyACM0"
baud = 57600
checksum = "crc"
[[line.drive]]
name = "press5/controller"
id = 5
[[line.drive]]
name = "press6/controller"
devicenet_macid = 6
colour = "red"
[[line]]
name = "rs485"
port = "/dev/ttyUSB0"
can_bitrate = 250000
[[line.drive]]
name = "press3/z"
id = 0x11
devicenet_macid = 5
devicenet_motors = "A"
)") == "plant.toml:4:1: 'baud' is a LinRS key, not for DeviceNet line 'can1' (port "
       "'slcan:/dev/ttyACM0' is a CAN link)\n"
       "plant.toml:5:1: 'checksum' is a LinRS key, not for DeviceNet line 'can1' (port "
       "'slcan:/dev/ttyACM0' is a CAN link)\n"
       "plant.toml:8:1: drive 'press5/controller': 'id' is a LinRS key, not for DeviceNet line "
       "'can1' (port 'slcan:/dev/ttyACM0' is a CAN link)\n"
       "plant.toml:6:1: drive 'press5/controller' has no 'devicenet_macid' (the controller's MAC "
       "ID 0..63, e.g. devicenet_macid = 5)\n"
       "plant.toml:12:1: unknown key 'colour' in drive of line 'can1' (known: name, "
       "devicenet_macid, devicenet_motors, io_modules, no_module_values, labels, ignore)\n"
       "plant.toml:16:1: 'can_bitrate' is a DeviceNet key, not for LinRS line 'rs485' "
       "(DeviceNet needs a CAN port: slcan:DEVICE, slcan:tcp://HOST:PORT, can0)\n"
       "plant.toml:20:1: drive 'press3/z': 'devicenet_macid' is a DeviceNet key, not for LinRS "
       "line 'rs485' (DeviceNet needs a CAN port: slcan:DEVICE, slcan:tcp://HOST:PORT, can0)\n"
       "plant.toml:21:1: drive 'press3/z': 'devicenet_motors' is a DeviceNet key, not for LinRS "
       "line 'rs485' (DeviceNet needs a CAN port: slcan:DEVICE, slcan:tcp://HOST:PORT, can0)");
}

TEST_CASE("fleet inventory: DeviceNet values are checked as the options of the same names",
          "[fleet][inventory][devicenet]") {
  CHECK(problems(R"([[line]]
name = "can1"
port = "vcan0"
[[line.drive]]
name = "a"
devicenet_macid = 64
[[line.drive]]
name = "b"
devicenet_macid = 1
devicenet_motors = "A,E"
io_modules = "control-in,warp-drive"
no_module_values = "yes"
[[line.drive]]
name = "c"
devicenet_macid = 1
)") == "plant.toml:6:19: drive 'a': devicenet_macid 64 is not a DeviceNet MAC ID 0..63\n"
       "plant.toml:10:20: devicenet_motors 'A,E': expected motors A..D, each once, e.g. A,B\n"
       "plant.toml:11:14: unknown IO module 'warp-drive' (expected control-in, addressed-in, "
       "direct-in, status-out, addressed-out, direct-out-1, direct-out-2, master:A..master:D)\n"
       "plant.toml:12:20: 'no_module_values' must be true or false");
  CHECK(problems(R"([[line]]
name = "can1"
port = "vcan0"
[[line.drive]]
name = "b"
devicenet_macid = 1
[[line.drive]]
name = "c"
devicenet_macid = 1
)") == "plant.toml:7:1: line 'can1': drives 'b' (plant.toml:4:1) and 'c' (plant.toml:7:1) both "
       "have DeviceNet MAC ID 01h");
}

TEST_CASE("fleet inventory: a DeviceNet line's adapter must exist, its gateway have a port",
          "[fleet][inventory][devicenet]") {
  auto inv = fleet::parse_inventory(R"([[line]]
name = "usb"
port = "slcan:/dev/no-such-can-adapter"
[[line.drive]]
name = "a"
devicenet_macid = 1
[[line]]
name = "gw"
port = "slcan:tcp://10.0.0.7"
[[line.drive]]
name = "b"
devicenet_macid = 1
[[line]]
name = "ok"
port = "can0"
[[line.drive]]
name = "c"
devicenet_macid = 1
)",
                                    "plant.toml");
  REQUIRE(inv.ok());
  auto ports = fleet::check_ports(*inv);
  REQUIRE_FALSE(ports.ok());
  CHECK(ports.error().message ==
        "plant.toml:1:1: line 'usb': port /dev/no-such-can-adapter does not exist (is the "
        "adapter plugged in?)\n"
        "plant.toml:7:1: line 'gw': port 'slcan:tcp://10.0.0.7' is not slcan:tcp://HOST:PORT "
        "with PORT 1..65535");
}

TEST_CASE("fleet inventory: a drive's optional family (docs/families.md), checked by name",
          "[fleet][inventory][families]") {
  const std::string text = R"([[line]]
name = "l1"
port = "/dev/ttyUSB0"
[[line.drive]]
name = "a"
id = 0x11
family = "c1100"
[[line.drive]]
name = "b"
id = 0x12
)";
  auto inv = fleet::parse_inventory(text, "plant.toml");
  REQUIRE(inv.ok());
  REQUIRE(inv->lines.at(0).drives.size() == 2);
  REQUIRE(inv->lines[0].drives[0].family);
  CHECK(inv->lines[0].drives[0].family->name == "C1100");
  CHECK(inv->lines[0].drives[1].family == nullptr);  // not named: the seeds' E1100
  CHECK(
      problems("[[line]]\nname = \"l1\"\nport = \"/dev/null\"\n[[line.drive]]\nname = \"a\"\nid = "
               "1\nfamily = \"Z1\"\n") ==
      "plant.toml:7:10: drive 'a': unknown drive family 'Z1'; expected one of E1100, B1100, "
      "C1100, E1200, E1400 (docs/families.md)");
}

TEST_CASE("fleet inventory: a linudp:// line holds one drive, named, without an id",
          "[fleet][inventory][linudp]") {
  auto inv = fleet::parse_inventory(R"([[line]]
name = "cell4"
port = "linudp://10.8.7.232"
[[line.drive]]
name = "cell4/gripper"
labels = { machine = "cell4" }
)",
                                    "plant.toml");
  REQUIRE(inv.ok());
  REQUIRE(inv->lines.size() == 1);
  CHECK(inv->lines[0].drives.size() == 1);
  CHECK_FALSE(inv->lines[0].devicenet);
  CHECK(problems(R"([[line]]
name = "cell4"
port = "linudp://10.8.7.232:49360"
[[line.drive]]
name = "cell4/a"
id = 0x11
[[line.drive]]
name = "cell4/b"
)") == "plant.toml:6:6: drive 'cell4/a': a linudp://10.8.7.232:49360 line reaches its drive by "
       "address; remove 'id'\n"
       "plant.toml:1:1: line 'cell4': a linudp:// port reaches one drive (its IP address, "
       "LinUDP V2 §3.2); give each drive a line of its own");
}

}  // namespace fleet_test_inventory
