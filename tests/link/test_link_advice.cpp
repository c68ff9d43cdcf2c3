// The wrong-parity hint (docs/reliability.md, errors that say what to do). A drive at even parity
// and the tool at none (or the reverse) must get advice naming --parity and `lmcfg scan`.
//
// Why not over a pseudo-terminal: Linux ptys force CS8 and clear PARENB
// (docs/transport.md), so the simulated drive behind `lmcfg sim` cannot see
// the master's parity, and `--port sim:FILE` wires the line at the drive's own
// settings. The decision (link::settings_suspect + link::link_advice, what
// `fail()` in tools/lmcfg/link_options.cpp prints as "lmcfg CMD: ADVICE",
// exit 4 for a timeout or garbled answers) is therefore tested here on a
// session whose simulated line runs at the tool's parity while the drive
// listens at its own: a UART at the wrong parity hears nothing it can decode
// (sim::Bus), or, in the other direction, hands the master mangled bytes.
#include <catch2/catch.hpp>

#include "e2e_support.hpp"
#include "link/link_advice.hpp"
#include "link/session.hpp"
#include "sim/link.hpp"

// This file's own namespace: the test binary is a unity build (tests/CMakeLists.txt).
namespace link_test_link_advice {

using namespace lmcfg;

namespace {

// The simulated line at the tool's settings, seen by the tools as a serial
// port. With `mangle`, what a master UART at the wrong parity makes of the
// drive's answers: every byte arrives misframed (the parity bit read as a stop
// bit shifts the frame), so nothing decodes. Modelled as the top bit flipped
// in every byte received.
class ParityLine final : public transport::Transport {
 public:
  ParityLine(std::shared_ptr<sim::Drive> drive, bool mangle)
      : sim_(std::move(drive)), mangle_(mangle) {}
  Result<void> write(ByteView b) override { return sim_.write(b); }
  Result<Bytes> read_some(transport::Millis t) override {
    auto r = sim_.read_some(t);
    if (r.ok() && mangle_)
      for (auto& b : *r) b = static_cast<std::uint8_t>(b ^ 0x80);
    return r;
  }
  void discard_input() override { sim_.discard_input(); }
  std::string describe() const override { return "serial /dev/ttyUSB0"; }
  double byte_time_us() const override { return sim_.byte_time_us(); }
  std::int64_t now_ns() const override { return sim_.now_ns(); }
  Result<void> reconfigure(const transport::SerialSettings& s) override {
    return sim_.reconfigure(s);
  }

 private:
  sim::SimLink sim_;
  bool mangle_;
};

// A session on a simulated line at the tool's settings (`line`); the drive
// keeps its own. relink() reconfigures the line, as on a serial port.
std::unique_ptr<link::Session> parity_session(std::shared_ptr<sim::Drive> drive,
                                              transport::SerialSettings line, bool mangle) {
  link::LinkSpec lo;
  lo.port = *link::parse_port("/dev/ttyUSB0");
  lo.serial = line;
  lo.serial.device = lo.port.address;
  lo.client.id = drive->macid();
  lo.client.timeout = transport::Millis(20);
  lo.client.read_retries = 0;
  lo.client.adaptive_deadline = lo.client.adaptive_settle = true;  // as link::open_session
  transport::OpenedLink opened;
  auto link = std::make_unique<ParityLine>(std::move(drive), mangle);
  REQUIRE(link->reconfigure(line).ok());
  opened.link = std::move(link);
  return std::make_unique<link::Session>(lo, lo.serial, std::move(opened), std::nullopt);
}

struct Outcome {
  Error error{Errc::ok, ""};
  bool suspect = false;
  std::optional<std::string> advice;
};

Outcome first_read(transport::Parity drive_parity, transport::Parity tool_parity, bool mangle) {
  auto drive = test::load_sim_drive("commissioned-axis.json");  // MACID 11h, 57600
  drive->state().link.parity = drive_parity;
  transport::SerialSettings line = drive->state().link;
  line.parity = tool_parity;
  auto session = parity_session(drive, line, mangle);
  auto& s = *session;
  auto r = s.client().read_rom(0x13A2);
  REQUIRE_FALSE(r.ok());
  Outcome o;
  o.error = r.error();
  o.suspect = link::settings_suspect(s, o.error);
  if (o.suspect) o.advice = link::link_advice(s, "/dev/ttyUSB0");
  return o;
}

}  // namespace

TEST_CASE("wrong parity: the advice names --parity and lmcfg scan", "[cli][advice][parity]") {
  const std::string silent =
      "no answer from MACID 11h at 57600 Bd: check --id and --baud (and --parity), or run "
      "`lmcfg scan --port /dev/ttyUSB0` to try every MACID and rate";
  const std::string garbled =
      "the drive's answers at 57600 Bd arrive garbled: check --parity and --stop-bits (factory "
      "setting 8N1) and --baud, or run `lmcfg scan --port /dev/ttyUSB0`";

  SECTION("drive at even parity, tool at none: the drive hears nothing it can decode") {
    auto o = first_read(transport::Parity::even, transport::Parity::none, false);
    CHECK(o.error.code == Errc::timeout);  // exit 4 (communication failure)
    CHECK(o.suspect);
    REQUIRE(o.advice);
    CHECK(*o.advice == silent);
  }
  SECTION("drive at no parity, tool at even: silent as well") {
    auto o = first_read(transport::Parity::none, transport::Parity::even, false);
    CHECK(o.error.code == Errc::timeout);
    CHECK(o.suspect);
    REQUIRE(o.advice);
    CHECK(*o.advice == silent);
  }
  SECTION("the drive answers but the master's UART mangles every byte") {
    // Both sides at the same parity for the drive to hear; the mangler plays
    // the master's misframing.
    auto o = first_read(transport::Parity::even, transport::Parity::even, true);
    CHECK(o.suspect);
    REQUIRE(o.advice);
    CHECK(*o.advice == garbled);
  }
}

}  // namespace link_test_link_advice
