// What a configuration tool reads from a DeviceNet controller
// (lib/devicenet/catalogue.cpp): the Get commands of DeviceNet §5.2 Table 5-1
// and their Sets, the IO module names, the option values, and frames'
// meaning for --trace.
#include <catch2/catch.hpp>

#include "devicenet/catalogue.hpp"
#include "devicenet/command.hpp"

// This file's own namespace: the test binary is a unity build (tests/CMakeLists.txt).
namespace devicenet_test_catalogue {

using namespace lmcfg;
using devicenet::Motor;

TEST_CASE("devicenet: frames' meaning for --trace (polls decoded with the layout, services named)",
          "[devicenet]") {
  const devicenet::IoLayout l;  // the default: 6 bytes out, 8 in
  CHECK(devicenet::describe_frame(can::Frame::standard(0x42D, Bytes{0, 0, 0x8A, 0x10, 0x34, 0x12}),
                                  l) ==
        "Group 2 MAC 05h master's I/O poll command: command 0Ah motor A toggle 1 value 1234h");
  CHECK(devicenet::describe_frame(
            can::Frame::standard(0x3C5, Bytes{0x43, 0, 0x80, 0, 0x0A, 0, 0x11, 0x81}), l) ==
        "Group 1 MAC 05h slave's I/O poll response (Fh): status 0043h 0080h, echo command 0Ah "
        "toggle 0 value 8111h");
  CHECK(
      devicenet::describe_frame(can::Frame::standard(0x42E, Bytes{0x3E, 0x4B, 3, 1, 3, 0x3E}), l) ==
      "Group 2 MAC 05h unconnected explicit request: Allocate_Master/Slave_Connection_Set "
      "request 03 01 03 3E");
}

TEST_CASE("DeviceNet §5.2 Table 5-1: settings have their Set at Get + 1, live values are apart",
          "[devicenet][catalogue]") {
  // Table 5-1: "0x24 Get (Rise) Curve Number 0 to 63", "0x25 Set (Rise) Curve
  // Number"; "0x40 Get Minimal Position", "0x41 Set Minimal Position".
  for (std::uint8_t get : std::initializer_list<std::uint8_t>{0x24, 0x26, 0x40}) {
    INFO(int(get));
    const auto* c = devicenet::value_command(get);
    REQUIRE(c != nullptr);
    CHECK(c->settable);
    CHECK(c->per_motor);
    CHECK_FALSE(c->live);
    CHECK_FALSE(c->needs_module);
  }
  // "0x02 Get Status Low Word", "0x03 Get Status High Word": no Set listed.
  const auto* status = devicenet::value_command(0x02);
  REQUIRE(status != nullptr);
  CHECK_FALSE(status->settable);
  CHECK(status->live);
  CHECK_FALSE(status->per_motor);
  // "0x60 Get Encoder 1 Position": only with the master encoder module.
  const auto* encoder = devicenet::value_command(0x60);
  REQUIRE(encoder != nullptr);
  CHECK(encoder->needs_module);
  CHECK(encoder->live);
  // A Set ID, and IDs Table 5-1 does not list, are not value commands.
  CHECK(devicenet::value_command(0x25) == nullptr);
  CHECK(devicenet::value_command(0x00) == nullptr);
  CHECK(devicenet::value_command(0xFF) == nullptr);
  // In command ID order; Warn and Error State are read for the controller and per motor.
  const auto all = devicenet::value_commands();
  REQUIRE(all.size() == 47);
  for (std::size_t i = 1; i < all.size(); ++i) CHECK(all[i - 1].get <= all[i].get);
  int warn = 0;
  for (const auto& c : all) warn += c.get == 0x06 ? 1 : 0;
  CHECK(warn == 2);
  for (const auto& c : all)
    if (c.get >= 0x24 && c.get < 0x60) CHECK((c.get % 2 == 0 && c.settable && !c.live));
}

TEST_CASE("devicenet catalogue: IO module names both ways, unknown ones named",
          "[devicenet][catalogue]") {
  const devicenet::IoLayout def;
  CHECK(devicenet::module_names(def) ==
        std::vector<std::string>{"control-in", "addressed-in", "status-out", "addressed-out"});
  auto l = devicenet::parse_modules("control-in,direct-in,direct-out-1,master:A,master:C");
  REQUIRE(l.ok());
  CHECK(l->control_in);
  CHECK_FALSE(l->addressed_in);
  CHECK(l->direct_in);
  CHECK_FALSE(l->status_out);
  CHECK(l->direct_out1);
  CHECK((l->masters == std::array<bool, 4>{true, false, true, false}));
  CHECK(devicenet::module_names(*l) == std::vector<std::string>{"control-in", "direct-in",
                                                                "direct-out-1", "master:A",
                                                                "master:C"});
  auto back = devicenet::parse_modules(devicenet::module_names(*l));
  REQUIRE(back.ok());
  CHECK(devicenet::module_names(*back) == devicenet::module_names(*l));
  // Without a master named, motor A carries the Direct modules.
  auto no_master = devicenet::parse_modules("status-out");
  REQUIRE(no_master.ok());
  CHECK((no_master->masters == std::array<bool, 4>{true, false, false, false}));
  auto bad = devicenet::parse_modules("control-in,master:E");
  REQUIRE_FALSE(bad.ok());
  CHECK(bad.error().code == make_error_code(Errc::invalid_argument));
  CHECK(bad.error().message ==
        "unknown IO module 'master:E' (expected control-in, addressed-in, direct-in, status-out, "
        "addressed-out, direct-out-1, direct-out-2, master:A..master:D)");
}

TEST_CASE("devicenet catalogue: MAC IDs 0..63 and motor lists, the option named in messages",
          "[devicenet][catalogue]") {
  CHECK(devicenet::parse_mac_id("--devicenet-macid", "63").value() == 63);
  CHECK(devicenet::parse_mac_id("--devicenet-macid", "0x3F").value() == 63);
  CHECK(devicenet::parse_mac_id("--devicenet-macid", "3Fh").value() == 63);
  CHECK(devicenet::parse_mac_id("--devicenet-macid", "0").value() == 0);
  auto high = devicenet::parse_mac_id("--devicenet-macid", "64");
  REQUIRE_FALSE(high.ok());
  CHECK(high.error().code == make_error_code(Errc::invalid_argument));
  CHECK(high.error().message == "--devicenet-macid '64' is not a DeviceNet MAC ID 0..63");
  CHECK(devicenet::parse_mac_id("devicenet_macid", "x").error().message ==
        "devicenet_macid 'x' is not a DeviceNet MAC ID 0..63");

  CHECK((devicenet::parse_motor_list("--devicenet-motors", "A,C").value() ==
         std::array<bool, 4>{true, false, true, false}));
  CHECK((devicenet::parse_motor_list("--devicenet-motors", "BD").value() ==
         std::array<bool, 4>{false, true, false, true}));
  CHECK((devicenet::parse_motor_list("--devicenet-motors", "").value() ==
         std::array<bool, 4>{false, false, false, false}));
  for (const char* bad : {"A,A", "E", "a", "A;B"}) {
    INFO(bad);
    auto r = devicenet::parse_motor_list("--devicenet-motors", bad);
    REQUIRE_FALSE(r.ok());
    CHECK(r.error().message == std::string("--devicenet-motors '") + bad +
                                   "': expected motors A..D, each once, e.g. A,B");
  }
  CHECK(devicenet::target_name(Motor::B) == "motor B");
  CHECK(devicenet::target_name(std::nullopt) == "the controller");
}

}  // namespace devicenet_test_catalogue
