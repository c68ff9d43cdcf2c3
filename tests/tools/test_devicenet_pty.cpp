// `lmcfg sim --devicenet`: the simulated DeviceNet controller behind a
// simulated slcan adapter on a real pseudo-terminal, reached by the master
// through the serial transport and the slcan link (the path a USB-CAN
// adapter takes).
#include <catch2/catch.hpp>

#include "can/link.hpp"
#include "devicenet/master.hpp"
#include "link/port.hpp"
#include "subprocess.hpp"

// This file's own namespace: the test binary is a unity build (tests/CMakeLists.txt).
namespace tools_test_devicenet_pty {

using namespace lmcfg;

TEST_CASE("devicenet: master -> slcan on a pty -> lmcfg sim --devicenet", "[devicenet][pty]") {
  test::Child sim({LMCFG_TOOL_PATH, "sim", "--devicenet", "--devicenet-macid", "10"});
  const std::string path = sim.read_line();
  REQUIRE(path.rfind("/dev/", 0) == 0);
  CHECK(sim.read_line() ==
        "link options: --port slcan:" + path + " --can-bitrate 125000 --devicenet-macid 10");
  std::vector<std::string> trace;
  auto link = link::open_can_link("slcan:" + path, {125000, true, transport::Millis(1000)});
  REQUIRE(link.ok());
  can::TraceLink traced(std::move(link).value(), [&](const std::string& l) { trace.push_back(l); });
  devicenet::MasterOptions o;
  o.slave_mac = 10;
  o.timeout = transport::Millis(1000);
  o.duplicate_check_wait = transport::Millis(50);
  {
    devicenet::Master m(traced, o);
    REQUIRE(m.check_own_mac().ok());
    REQUIRE(m.connect().ok());
    CHECK(m.granted_packet_rate() == 2000);
    auto set = m.command({true, false, false, false}, 0x2D, 1024);  // Set Curve Speed, motor A
    REQUIRE(set.ok());
    auto get = m.command({true, false, false, false}, 0x2C, 0);
    REQUIRE(get.ok());
    CHECK(*get == 1024);
  }                                           // released here
  CHECK(trace.back() == "RX 453 [2] 3E CC");  // Release answered by MAC 10 (0x453)
  CHECK(sim.stop() == 0);
}

}  // namespace tools_test_devicenet_pty
