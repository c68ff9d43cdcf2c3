// The one link specification (lib/link/spec): every source of link settings
// (the tool's options, an inventory line, a Python call) goes through
// make_link_spec, and a session opened from a spec never changes it.
#include <catch2/catch.hpp>
#include <filesystem>

#include "fleet/inventory.hpp"
#include "link/spec.hpp"

// This file's own namespace: the test binary is a unity build (tests/CMakeLists.txt).
namespace link_test_spec {

using namespace lmcfg;

namespace {

std::string problem(const link::LinkInput& in, const link::InputNames& names = link::kOptionNames) {
  auto s = link::make_link_spec(in, names);
  REQUIRE_FALSE(s.ok());
  CHECK(s.error().code == Errc::invalid_argument);
  return s.error().message;
}

link::LinkInput serial_input() {
  link::LinkInput in;
  in.port = "/dev/ttyUSB0";
  return in;
}

}  // namespace

TEST_CASE("link spec: the options' values are checked with their option names", "[link][spec]") {
  auto in = serial_input();
  in.id = "300";
  CHECK(problem(in) == "--id '300' is not a MACID 0..255 (0x00..0xFF)");
  in = serial_input();
  in.id = "0x1FF";
  CHECK(problem(in) == "--id '0x1FF' is not a MACID 0..255 (0x00..0xFF)");
  in = serial_input();
  in.timeout_ms = 0;
  CHECK(problem(in) == "--timeout-ms 0 is outside 1..60000");
  in = serial_input();
  in.settle_ms = 0;
  CHECK(problem(in) == "--settle-ms 0 is outside 1..60000");
  in = serial_input();
  in.retries = 99;
  CHECK(problem(in) == "--retries 99 is outside 0..10");
  in = serial_input();
  in.long_timeout_s = 4000;
  CHECK(problem(in) == "--long-timeout-s 4000 is outside 1..3600");
  in = serial_input();
  in.agreeing_reads = "twice";
  CHECK(problem(in) == "--agreeing-reads 'twice' is not auto or 1..5");
  in = serial_input();
  in.agreeing_reads = "0";
  CHECK(problem(in) == "--agreeing-reads '0' is not auto or 1..5");
  in = serial_input();
  in.checksum = "sha1";
  CHECK(problem(in) ==
        "checksum 'sha1' is not one of none, add, crc, crc-ffff, crc-0000, crc-kermit");
  in = serial_input();
  in.checksum_coverage = "all";
  CHECK(problem(in) == "checksum coverage 'all' is not one of id, start, data");
  in = serial_input();
  in.parity = "maybe";
  CHECK(problem(in) == "parity 'maybe' is not one of none, even, odd");
  in = serial_input();
  in.baud = 1234;
  CHECK(problem(in).rfind("unsupported baud rate 1234 (allowed: ", 0) == 0);
  in = serial_input();
  in.stop_bits = 3;
  CHECK(problem(in) == "unsupported stop bits 3 (allowed: 1, 2)");
  in = serial_input();
  in.response_layout = "everything";
  CHECK(problem(in) ==
        "--response-layout 'everything' is not auto, factory or a comma list of comm_state, "
        "status_word, state_var, error_code, warn_word, echo_header, monitoring_1, "
        "monitoring_2, mc_response");
}

TEST_CASE("link spec: the port is parsed by its scheme's row, after the other settings",
          "[link][spec]") {
  link::LinkInput in;
  in.port = "";
  CHECK(problem(in) == "no --port given (a serial device, tcp://host:port or sim:FILE)");
  in.port = "tcp://10.0.0.5";
  CHECK(problem(in) == "port 'tcp://10.0.0.5' is not tcp://HOST:PORT with PORT 1..65535");
  // A bad setting is named before a bad port, as the tool has always done.
  in.id = "300";
  CHECK(problem(in) == "--id '300' is not a MACID 0..255 (0x00..0xFF)");
  // Every check but the port's, for callers that check ports on their own.
  in.id = "0x11";
  CHECK(link::check_link_settings(in).ok());
}

TEST_CASE("link spec: built from the options, with what each option sets", "[link][spec]") {
  auto in = serial_input();
  in.baud = 115200;
  in.parity = "even";
  in.stop_bits = 2;
  in.id = "2Ah";
  in.checksum = "crc-kermit";
  in.checksum_coverage = "start";
  in.timeout_ms = 50;
  in.settle_ms = 30;
  in.retries = 4;
  in.long_timeout_s = 9;
  in.agreeing_reads = "3";
  in.response_layout = "factory";
  in.trace = "wire.trace";
  in.holder = "lmcfg backup";
  const auto s = link::make_link_spec(in);
  REQUIRE(s.ok());
  CHECK(s->port.text == "/dev/ttyUSB0");
  CHECK(s->port.scheme_name() == "serial");
  CHECK(s->serial.device == "/dev/ttyUSB0");
  CHECK(s->serial.baud == 115200);
  CHECK(s->serial.parity == transport::Parity::even);
  CHECK(s->serial.stop_bits == 2);
  CHECK(s->client.id == 0x2A);
  CHECK(s->client.checksum.mode == codec::ChecksumMode::crc_kermit);
  CHECK(s->client.checksum.coverage == codec::ChecksumCoverage::start_through_data);
  CHECK(s->client.timeout == transport::Millis(50));
  CHECK(s->client.settle == transport::Millis(30));
  CHECK(s->fixed_settle);
  CHECK(s->client.read_retries == 4);
  CHECK(s->client.defaulting_timeout == transport::Millis(9000));
  CHECK(s->client.flash_timeout == transport::Millis(9000));
  CHECK(s->client.reset_timeout == transport::Millis(9000));
  CHECK(s->agreeing_reads == 3);
  CHECK_FALSE(s->client.adapt_layout);
  CHECK(s->trace_path == "wire.trace");
  CHECK(s->holder == "lmcfg backup");
  // A gateway's spec names no serial device.
  in.port = "tcp://10.0.0.5:4001";
  const auto gw = link::make_link_spec(in);
  REQUIRE(gw.ok());
  CHECK(gw->port.host == "10.0.0.5");
  CHECK(gw->port.tcp_port == 4001);
  CHECK(gw->serial.device.empty());
  // Another drive of the same line: only the MACID differs.
  const auto other = s->for_macid(0x12);
  CHECK(other.client.id == 0x12);
  CHECK(s->client.id == 0x2A);
  CHECK(other.port.text == s->port.text);
}

TEST_CASE("link spec: Python's arguments are checked by the same function, in its words",
          "[link][spec][python]") {
  auto in = serial_input();
  in.id = "300";
  CHECK(problem(in, link::kPythonNames) == "id 300 is not a MACID 0..255 (0x00..0xFF)");
  in = serial_input();
  in.timeout_ms = 0;
  CHECK(problem(in, link::kPythonNames) == "timeout_ms 0 is outside 1..60000");
  in = serial_input();
  in.retries = 11;
  CHECK(problem(in, link::kPythonNames) == "retries 11 is outside 0..10");
  in = serial_input();
  in.agreeing_reads = "7";
  CHECK(problem(in, link::kPythonNames) == "agreeing_reads 7 is not 0 (automatic) or 1..5");
}

TEST_CASE("link spec: an inventory line's keys over the options, problems at the line",
          "[link][spec][fleet]") {
  const std::string text = R"([[line]]
name = "l1"
port = "tcp://10.0.0.5:4001"
baud = 19200
checksum = "crc"
timeout_ms = 80
[[line.drive]]
name = "a"
id = 0x11
[[line]]
name = "l2"
port = "/dev/ttyUSB1"
retries = 11
[[line.drive]]
name = "b"
id = 0x12
)";
  auto inv = fleet::parse_inventory(text, "plant.toml");
  REQUIRE(inv.ok());
  link::LinkInput base;
  base.holder = "lmcfg fleet backup";
  base.retries = 3;
  const auto l1 = fleet::line_link_spec(inv->lines[0], base);
  REQUIRE(l1.ok());
  CHECK(l1->port.text == "tcp://10.0.0.5:4001");
  CHECK(l1->serial.baud == 19200);
  CHECK(l1->client.checksum.mode == codec::ChecksumMode::crc_ccitt);
  CHECK(l1->client.timeout == transport::Millis(80));
  CHECK(l1->client.read_retries == 3);
  CHECK(l1->holder == "lmcfg fleet backup");
  const auto l2 = fleet::line_link_spec(inv->lines[1], base);
  REQUIRE_FALSE(l2.ok());
  CHECK(l2.error().message == "plant.toml:10:1: line 'l2': --retries 11 is outside 0..10");
  CHECK(fleet::check_line_link(inv->lines[1], base).error().message ==
        "plant.toml:10:1: line 'l2': --retries 11 is outside 0..10");
}

}  // namespace link_test_spec
