// The session on a LinRS link (lib/link/session): opened from a link spec
// through the table of port schemes, closed once, and never changing its spec.
#include <catch2/catch.hpp>
#include <filesystem>

#include "e2e_support.hpp"
#include "files.hpp"
#include "link/session.hpp"
#include "link/spec.hpp"
#include "sim/state_file.hpp"
#include "sim_ports.hpp"

// This file's own namespace: the test binary is a unity build (tests/CMakeLists.txt).
namespace link_test_session {

using namespace lmcfg;

TEST_CASE("link schemes: a registered scheme opens its port, the factory's close runs once",
          "[session]") {
  REQUIRE(test::kSimPortsRegistered);
  int opened = 0, closed = 0;
  link::register_scheme(
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
  link::LinkSpec lo;
  lo.port = *link::parse_port("counting:some/where");
  lo.real_time_sim = true;
  auto s = link::open_session(lo);
  REQUIRE(s.ok());
  CHECK(opened == 1);
  // The simulated drive dictates the line: its state file says 57600 8N1.
  CHECK((*s)->line().baud == 57600);
  REQUIRE((*s)->close().ok());
  REQUIRE((*s)->close().ok());
  CHECK(closed == 1);
}

TEST_CASE("link schemes: an unregistered scheme is a serial device path", "[session]") {
  link::LinkSpec lo;
  lo.port = *link::parse_port("nosuchscheme:/nowhere");
  auto s = link::open_session(lo);
  REQUIRE_FALSE(s.ok());
  CHECK(s.error().message.find("nosuchscheme:/nowhere") != std::string::npos);
}

TEST_CASE("link spec: a session never changes its spec, relink gives the spec of the link now",
          "[link][spec][session]") {
  REQUIRE(test::kSimPortsRegistered);
  test::ScratchDir dir("session");
  std::filesystem::copy_file(test::sim_fixture("commissioned-axis.json"), dir.path / "axis.json");
  link::LinkInput in;
  in.port = "sim:" + (dir.path / "axis.json").string();
  in.id = "0x11";
  const auto spec = link::make_link_spec(in);
  REQUIRE(spec.ok());
  auto s = link::open_session(*spec);
  REQUIRE(s.ok());
  CHECK(&(*s)->spec() != &*spec);
  CHECK((*s)->spec().client.id == 0x11);
  // The session's client has what the link decides on top of the spec.
  CHECK((*s)->client().options().adaptive_deadline);
  CHECK_FALSE(spec->client.adaptive_deadline);
  transport::SerialSettings line = (*s)->line();
  line.baud = 38400;
  codec::ChecksumConfig add;
  add.mode = codec::ChecksumMode::add;
  REQUIRE((*s)->relink(line, 0x22, add).ok());
  CHECK((*s)->spec().client.id == 0x11);
  CHECK((*s)->spec().client.checksum.mode == codec::ChecksumMode::none);
  const auto now = (*s)->current_spec();
  CHECK(now.client.id == 0x22);
  CHECK(now.client.checksum.mode == codec::ChecksumMode::add);
  CHECK(now.serial.baud == 38400);
  CHECK(now.port.text == spec->port.text);
  CHECK((*s)->link_settings().checksum == "add");
  CHECK((*s)->link_settings().baud == "38400");
  REQUIRE((*s)->close().ok());
}

}  // namespace link_test_session
