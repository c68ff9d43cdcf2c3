// Port schemes: the operations layer opens serial ports and TCP gateways
// itself; "sim:" is registered by the program (tools/lmcfg/main.cpp) and, the
// same way, by this test binary for every test that uses sim: ports.
#include <catch2/catch.hpp>
#include <filesystem>
#include <fstream>

#include "common/bytes.hpp"
#include "ops/session.hpp"
#include "sim/state_file.hpp"

namespace {
const bool kSimPortsRegistered = [] {
  lmcfg::ops::register_link_scheme("sim", lmcfg::sim::state_file_link_factory());
  return true;
}();
}  // namespace

using namespace lmcfg;

TEST_CASE("link schemes: a registered scheme opens its port; the factory's close runs once",
          "[session]") {
  REQUIRE(kSimPortsRegistered);
  int opened = 0, closed = 0;
  ops::register_link_scheme(
      "counting", [&](const transport::LinkRequest& req) -> Result<transport::OpenedLink> {
        ++opened;
        CHECK(req.address == "some/where");
        CHECK(req.real_time_peer);
        LMCFG_ASSIGN_OR_RETURN(
            auto inner, sim::state_file_link_factory()(transport::LinkRequest{
                            LMCFG_SOURCE_DIR "/tests/fixtures/sim/commissioned-axis.json", false}));
        inner.on_close = [&closed]() -> Result<void> {
          ++closed;
          return {};
        };
        return inner;
      });
  ops::LinkOptions lo;
  lo.port = "counting:some/where";
  lo.real_time_sim = true;
  auto s = ops::open_session(lo);
  REQUIRE(s.ok());
  CHECK(opened == 1);
  // The simulated drive dictates the line: its state file says 57600 8N1.
  CHECK((*s)->line().baud == 57600);
  REQUIRE((*s)->close().ok());
  REQUIRE((*s)->close().ok());
  CHECK(closed == 1);
}

TEST_CASE("link schemes: an unregistered scheme is a serial device path", "[session]") {
  ops::LinkOptions lo;
  lo.port = "nosuchscheme:/nowhere";
  auto s = ops::open_session(lo);
  REQUIRE_FALSE(s.ok());
  CHECK(s.error().message.find("nosuchscheme:/nowhere") != std::string::npos);
}

TEST_CASE("hex: the one formatter pads, never truncates, and appends the suffix", "[common]") {
  CHECK(hex(0x13A2, 4) == "13A2");
  CHECK(hex(0x11, 2, "h") == "11h");
  CHECK(hex(0x5, 2) == "05");
  CHECK(hex(0, 1) == "0");
  CHECK(hex(0x12345, 4) == "12345");
  CHECK(hex(0xFFFFFFFFu, 8, "h") == "FFFFFFFFh");
}
