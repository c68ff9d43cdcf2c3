// sim::LinudpLink (lib/sim/linudp_link.*): replies on the virtual clock.
#include <catch2/catch.hpp>

#include "e2e_support.hpp"
#include "sim/linudp_link.hpp"

// This file's own namespace: the test binary is a unity build (tests/CMakeLists.txt).
namespace sim_test_linudp_link {

using namespace lmcfg;

TEST_CASE("LinUDP sim link: a reply after its delay, a timeout advances the clock only",
          "[linudp][sim]") {
  auto udp = std::make_shared<sim::LinudpDrive>(test::load_sim_drive("commissioned-axis.json"));
  sim::LinudpLink link(udp);
  linudp::RtcBlock r;
  r.count = 2;
  REQUIRE(link.write(linudp::encode_request(r)).ok());
  auto got = link.read_some(transport::Millis(200));
  REQUIRE(got.ok());
  CHECK(got->size() == 64);
  CHECK(link.now_ns() < 2'000'000);  // turnaround and network time, no wall clock
  auto none = link.read_some(transport::Millis(5000));
  REQUIRE(none.ok());
  CHECK(none->empty());
  CHECK(link.now_ns() > 5'000'000'000);
}

}  // namespace sim_test_linudp_link
