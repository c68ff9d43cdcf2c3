// The fleet inventory (lib/fleet/inventory, docs/fleet.md): the form scripts
// write, and every kind of bad inventory with its exact message and position.
#include <catch2/catch.hpp>

#include "files.hpp"
#include "fleet/inventory.hpp"

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
       "ignore, on_replaced)\n"
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
        "labels, ignore)");
}
