// Port schemes: the operations layer opens serial ports and TCP gateways
// itself; "sim:" is registered by the program (tools/lmcfg/main.cpp) and, the
// same way, by this test binary for every test that uses sim: ports.
#include <catch2/catch.hpp>
#include <filesystem>
#include <fstream>

#include "common/bytes.hpp"
#include "link/port.hpp"
#include "link/session.hpp"
#include "link/spec.hpp"
#include "sim_ports.hpp"

// This file's own namespace: the test binary is a unity build (tests/CMakeLists.txt).
namespace link_test_port {

using namespace lmcfg;

TEST_CASE("hex: the one formatter pads, never truncates, and appends the suffix", "[common]") {
  CHECK(hex(0x13A2, 4) == "13A2");
  CHECK(hex(0x11, 2, "h") == "11h");
  CHECK(hex(0x5, 2) == "05");
  CHECK(hex(0, 1) == "0");
  CHECK(hex(0x12345, 4) == "12345");
  CHECK(hex(0xFFFFFFFFu, 8, "h") == "FFFFFFFFh");
}

TEST_CASE("port schemes: one row per kind of port, each with its parser, kind and line rate",
          "[session][link]") {
  REQUIRE(test::kSimPortsRegistered);
  struct Row {
    const char* port;
    const char* scheme;
    link::Kind kind;
    bool line_rate;
    const char* address;
  };
  const Row rows[] = {
      {"/dev/ttyUSB0", "serial", link::Kind::byte_link, true, "/dev/ttyUSB0"},
      {"tcp://10.0.0.5:4001", "tcp", link::Kind::byte_link, false, "10.0.0.5:4001"},
      {"rfc2217://gw:2217", "rfc2217", link::Kind::byte_link, true, "gw:2217"},
      {"sim:axis.json", "sim", link::Kind::byte_link, true, "axis.json"},
      {"slcan:/dev/ttyACM0", "slcan", link::Kind::can_link, false, "/dev/ttyACM0"},
      {"slcan:tcp://127.0.0.1:4002", "slcan-tcp", link::Kind::can_link, false, "127.0.0.1:4002"},
      {"can0", "socketcan", link::Kind::can_link, false, "can0"},
      {"vcan12", "socketcan", link::Kind::can_link, false, "vcan12"},
      {"canopen", "serial", link::Kind::byte_link, true, "canopen"},
  };
  for (const auto& r : rows) {
    INFO(r.port);
    auto spec = link::parse_port(r.port);
    REQUIRE(spec.ok());
    CHECK(spec->scheme_name() == r.scheme);
    CHECK(spec->kind() == r.kind);
    CHECK(spec->sets_line_rate() == r.line_rate);
    CHECK(spec->address == r.address);
    CHECK(link::is_can_port(r.port) == (r.kind == link::Kind::can_link));
  }
  auto v6 = link::parse_port("tcp://[::1]:4001");
  REQUIRE(v6.ok());
  CHECK(v6->host == "::1");
  CHECK(v6->tcp_port == 4001);
  for (const char* bad :
       {"tcp://10.0.0.5", "tcp://:4001", "tcp://h:0", "tcp://h:65536", "tcp://h:x"})
    CHECK(link::parse_port(bad).error().message ==
          "port '" + std::string(bad) + "' is not tcp://HOST:PORT with PORT 1..65535");
  CHECK(link::parse_port("rfc2217://gw").error().message ==
        "port 'rfc2217://gw' is not rfc2217://HOST:PORT with PORT 1..65535");
  CHECK(link::parse_port("slcan:").error().message == "port 'slcan:' is not slcan:DEVICE");
  CHECK(link::parse_port("slcan:tcp://gw").error().message ==
        "port 'slcan:tcp://gw' is not slcan:tcp://HOST:PORT with PORT 1..65535");
  auto slcan_tcp = link::parse_port("slcan:tcp://[::1]:4002");
  REQUIRE(slcan_tcp.ok());
  CHECK(slcan_tcp->host == "::1");
  CHECK(slcan_tcp->tcp_port == 4002);
}

TEST_CASE("port schemes: slcan:tcp:// opens the adapter protocol over TCP, a CAN link only",
          "[link]") {
  // Nothing listens on the discard port of loopback: the row tried the connection.
  auto can = link::open_can_link("slcan:tcp://127.0.0.1:9", can::SlcanOptions{});
  REQUIRE_FALSE(can.ok());
  CHECK(can.error().message == "tcp 127.0.0.1:9: cannot connect: Connection refused");
  link::LinkSpec lo;
  lo.port = *link::parse_port("slcan:tcp://127.0.0.1:9");
  CHECK(link::open_session(lo).error().message ==
        "port 'slcan:tcp://127.0.0.1:9' is a CAN link (DeviceNet controllers), not a LinRS "
        "serial line");
}

TEST_CASE("port schemes: the session opens byte links only, rfc2217 through its transport",
          "[session][link]") {
  link::LinkSpec lo;
  // Nothing listens on the discard port of loopback: the row tried the connection.
  lo.port = *link::parse_port("rfc2217://127.0.0.1:9");
  auto rfc = link::open_session(lo);
  REQUIRE_FALSE(rfc.ok());
  CHECK(rfc.error().message == "rfc2217 127.0.0.1:9: cannot connect: Connection refused");
  lo.port = *link::parse_port("can0");
  auto can = link::open_session(lo);
  REQUIRE_FALSE(can.ok());
  CHECK(can.error().code == Errc::invalid_argument);
  CHECK(can.error().message ==
        "port 'can0' is a CAN link (DeviceNet controllers), not a LinRS serial line");
  // A port its row cannot parse is refused where the spec is built, before any open.
  link::LinkInput bad;
  bad.port = "tcp://127.0.0.1:0";
  CHECK(link::make_link_spec(bad).error().message ==
        "port 'tcp://127.0.0.1:0' is not tcp://HOST:PORT with PORT 1..65535");
}

TEST_CASE("port schemes: a registered factory gets the line settings and the holder",
          "[session][link]") {
  transport::LinkRequest seen;
  link::register_scheme("probe",
                        [&](const transport::LinkRequest& req) -> Result<transport::OpenedLink> {
                          seen = req;
                          return Error(Errc::not_supported, "probe: recorded");
                        });
  link::LinkSpec lo;
  lo.port = *link::parse_port("probe:x");
  lo.serial.baud = 19200;
  lo.serial.parity = transport::Parity::even;
  lo.holder = "lmcfg backup";
  CHECK(link::open_session(lo).error().message == "probe: recorded");
  CHECK(seen.address == "x");
  CHECK(seen.line.baud == 19200);
  CHECK(seen.line.parity == transport::Parity::even);
  CHECK(seen.holder == "lmcfg backup");
}

TEST_CASE("port schemes: HOST:PORT splits at the last colon", "[link]") {
  auto hp = link::split_host_port("127.0.0.1:0");
  REQUIRE(hp);
  CHECK(hp->host == "127.0.0.1");
  CHECK(hp->port == 0);
  CHECK(link::split_host_port("[::1]:80")->host == "::1");
  CHECK_FALSE(link::split_host_port("localhost"));
  CHECK_FALSE(link::split_host_port("h:70000"));
  CHECK_FALSE(link::split_host_port("h:"));
}

TEST_CASE("port table: linudp://HOST[:PORT] with the drive port 49360 by default",
          "[link][port][linudp]") {
  auto a = link::parse_port("linudp://10.8.7.232");
  REQUIRE(a.ok());
  CHECK(a->scheme_name() == "linudp");
  CHECK(a->protocol() == link::Protocol::linudp);
  CHECK(a->host == "10.8.7.232");
  CHECK(a->tcp_port == 49360);  // LinUDP V2 §4.3
  CHECK_FALSE(a->sets_line_rate());
  CHECK(a->kind() == link::Kind::byte_link);
  auto b = link::parse_port("linudp://drive7.plant:50000");
  REQUIRE(b.ok());
  CHECK(b->host == "drive7.plant");
  CHECK(b->tcp_port == 50000);
  CHECK(link::parse_port("/dev/ttyUSB0")->protocol() == link::Protocol::linrs);
  for (const char* bad :
       {"linudp://", "linudp://h:0", "linudp://h:x", "linudp://[::1]:5", "linudp://a/b"}) {
    auto r = link::parse_port(bad);
    REQUIRE_FALSE(r.ok());
    CHECK(r.error().message == "port '" + std::string(bad) +
                                   "' is not linudp://HOST[:PORT] (an IPv4 address or name, PORT "
                                   "1..65535)");
  }
}

}  // namespace link_test_port
