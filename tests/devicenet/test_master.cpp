// The DeviceNet master (lib/devicenet/master) against the simulated DeviceNet
// LinMot controller (lib/sim/devicenet_controller) on an in-process CAN bus:
// duplicate MAC ID check, allocation, the expected packet rate, the §5.2
// command exchange with its toggle under each reading of the seed's toggle
// rule the simulator plays, coded errors, lost poll responses,
// another master holding the connection, fragmented I/O, Release.
#include <catch2/catch.hpp>

#include "can/virtual_bus.hpp"
#include "devicenet/master.hpp"
#include "sim/devicenet_controller.hpp"

// This file's own namespace: the test binary is a unity build (tests/CMakeLists.txt).
namespace devicenet_test_master {

using namespace lmcfg;
using devicenet::Motor;

namespace {

struct Rig {
  std::shared_ptr<can::VirtualBus> bus = std::make_shared<can::VirtualBus>();
  sim::DeviceNetController controller;
  std::unique_ptr<can::Link> link;
  std::vector<std::string> trace;
  std::unique_ptr<can::TraceLink> traced;
  devicenet::Master master;

  static devicenet::MasterOptions options(const devicenet::IoLayout& layout) {
    devicenet::MasterOptions o;
    o.slave_mac = 0x3F;
    o.own_mac = 0x3E;
    o.layout = layout;
    o.timeout = transport::Millis(20);
    o.duplicate_check_wait = transport::Millis(10);
    return o;
  }
  static sim::DeviceNetControllerOptions controller_options(const devicenet::IoLayout& layout,
                                                            std::array<bool, 4> motors,
                                                            sim::ToggleRule rule,
                                                            sim::AbsentMotor absent) {
    sim::DeviceNetControllerOptions o;
    o.mac = 0x3F;
    o.layout = layout;
    o.motors = motors;
    o.toggle_rule = rule;
    o.absent_motor = absent;
    return o;
  }
  explicit Rig(devicenet::IoLayout layout = {},
               std::array<bool, 4> motors = {true, false, false, false},
               sim::ToggleRule rule = sim::ToggleRule::seed,
               sim::AbsentMotor absent = sim::AbsentMotor::coded_error)
      : controller(controller_options(layout, motors, rule, absent)),
        link(bus->open("master")),
        traced(std::make_unique<can::TraceLink>(
            std::move(link), [this](const std::string& l) { trace.push_back(l); },
            [](const can::Frame& f, bool) { return devicenet::describe_identifier(f.id); })),
        master(*traced, options(layout)) {
    controller.attach(*bus);
  }
};

constexpr std::array<bool, 4> kMotorA{true, false, false, false};

}  // namespace

TEST_CASE("devicenet master: connect, set and read back a curve number, release",
          "[devicenet][master]") {
  Rig rig;
  REQUIRE(rig.master.check_own_mac().ok());
  REQUIRE(rig.master.connect().ok());
  CHECK(rig.controller.allocated_by() == 0x3E);
  CHECK(rig.master.granted_packet_rate() == 2000);
  auto set = rig.master.command(kMotorA, 0x25, 7);  // Set (Rise) Curve Number
  REQUIRE(set.ok());
  CHECK(*set == 7);
  CHECK(rig.controller.value(Motor::A, 0x24) == 7);
  auto get = rig.master.command(kMotorA, 0x24, 0);  // Get (Rise) Curve Number
  REQUIRE(get.ok());
  CHECK(*get == 7);
  // Set and get: the first poll's No Command carries toggle 0, which the
  // controller toggle already is after power-up, so it does not run.
  CHECK(rig.controller.commands_executed() == 2);
  REQUIRE(rig.master.release().ok());
  CHECK_FALSE(rig.controller.allocated_by());
  // The trace names each frame's DeviceNet meaning.
  REQUIRE(rig.trace.size() >= 4);
  CHECK(rig.trace[0] == "TX 5F7 [7] 00 00 00 46 43 4D 4C  Group 2 MAC 3Eh duplicate MAC ID check");
  CHECK(rig.trace[2] ==
        "TX 5FE [6] 3E 4B 03 01 03 3E  Group 2 MAC 3Fh unconnected explicit request");
  CHECK(rig.trace[3] ==
        "RX 5FB [3] 3E CB 00  Group 2 MAC 3Fh slave's explicit/unconnected response");
}

TEST_CASE("devicenet master: repeating a poll does not execute a command twice",
          "[devicenet][master]") {
  Rig rig;
  REQUIRE(rig.master.connect().ok());
  REQUIRE(rig.master.command(kMotorA, 0x25, 3).ok());
  const auto executed = rig.controller.commands_executed();
  devicenet::PollCommand same;
  same.addressed =
      devicenet::CommandWord{kMotorA, !rig.master.last_status().command_toggle(Motor::A), 0x25};
  // A poll with the toggle the controller already saw: no new execution.
  same.addressed.toggle = rig.master.last_status().command_toggle(Motor::A);
  same.addressed_value = 9;
  REQUIRE(rig.master.poll(same).ok());
  CHECK(rig.controller.commands_executed() == executed);
  CHECK(rig.controller.value(Motor::A, 0x24) == 3);
}

TEST_CASE("devicenet master: a value out of Table 5-1's range is the controller's coded error",
          "[devicenet][master]") {
  Rig rig;
  REQUIRE(rig.master.connect().ok());
  auto r = rig.master.command(kMotorA, 0x25, 64);  // curve numbers 0..63
  REQUIRE_FALSE(r.ok());
  CHECK(r.error().code == make_error_code(Errc::drive_refused));
  CHECK(r.error().message ==
        "command 25h to DeviceNet MAC ID 63: the controller reports an error, coded error 8118h "
        "Range error");
  CHECK(rig.master.last_coded_error() == 0x8118);
  // The master reset the error it caused (0Bh), so the next command's own
  // error is told apart: motor B is not a master drive of this controller.
  auto b = rig.master.command({false, true, false, false}, 0x24, 0);
  REQUIRE_FALSE(b.ok());
  CHECK(b.error().message ==
        "command 24h to DeviceNet MAC ID 63: the controller reports an error, coded error 8111h "
        "Drive not master");
  CHECK(rig.master.command(kMotorA, 0x24, 0).ok());
}

TEST_CASE(
    "devicenet master: lost poll responses are polled again, too many fail in bounded "
    "time",
    "[devicenet][master]") {
  Rig rig;
  REQUIRE(rig.master.connect().ok());
  rig.controller.drop_poll_responses(2);
  auto r = rig.master.command(kMotorA, 0x25, 5);
  REQUIRE(r.ok());
  CHECK(rig.controller.value(Motor::A, 0x24) == 5);
  rig.controller.drop_poll_responses(100);
  auto lost = rig.master.poll({});
  REQUIRE_FALSE(lost.ok());
  CHECK(lost.error().message ==
        "no poll response from DeviceNet MAC ID 63 within 20 ms (after 3 polls)");
}

TEST_CASE(
    "devicenet master: another master holding the connection, a silent slave, a MAC ID "
    "taken",
    "[devicenet][master]") {
  {
    Rig rig;
    rig.controller.hold_for_other_master(0x00);
    auto r = rig.master.connect();
    REQUIRE_FALSE(r.ok());
    CHECK(r.error().message ==
          "DeviceNet MAC ID 63 refused the connection: error response to "
          "Allocate_Master/Slave_Connection_Set 4Bh: general error 0Ch object state conflict, "
          "additional 01h; another master (a PLC's scanner) probably holds it: the controller "
          "serves one master at a time (seed 000 §2.6)");
  }
  {
    auto bus = std::make_shared<can::VirtualBus>();
    auto link = bus->open("master");
    auto o = Rig::options({});
    o.slave_mac = 0x05;  // nobody there
    devicenet::Master m(*link, o);
    auto r = m.connect();
    REQUIRE_FALSE(r.ok());
    CHECK(r.error().code == make_error_code(Errc::timeout));
    CHECK(r.error().message ==
          "no answer from DeviceNet MAC ID 5 to Allocate_Master/Slave_Connection_Set within 20 "
          "ms on virtual CAN master: check --can-bitrate (125000, 250000 or 500000), "
          "--devicenet-macid and the cabling");
  }
  {
    auto bus = std::make_shared<can::VirtualBus>();
    sim::DeviceNetController other({0x3E, {}, kMotorA});  // a controller at the tool's MAC ID
    other.attach(*bus);
    auto link = bus->open("master");
    devicenet::Master m(*link, Rig::options({}));
    auto r = m.check_own_mac();
    REQUIRE_FALSE(r.ok());
    CHECK(r.error().message ==
          "DeviceNet MAC ID 62 (this tool's) is already used on the bus by another node: choose "
          "another with --devicenet-own-macid");
  }
}

TEST_CASE(
    "devicenet master: a controller reset mid-session drops the connection, reconnecting "
    "restores it",
    "[devicenet][master]") {
  Rig rig;
  REQUIRE(rig.master.connect().ok());
  REQUIRE(rig.master.command(kMotorA, 0x29, 100).ok());  // Set Curve Offset
  rig.controller.reset();
  auto r = rig.master.command(kMotorA, 0x28, 0);
  REQUIRE_FALSE(r.ok());
  CHECK(r.error().code == make_error_code(Errc::timeout));
  REQUIRE(rig.master.connect().ok());
  auto again = rig.master.command(kMotorA, 0x28, 0);
  REQUIRE(again.ok());
  CHECK(*again == 100);  // runtime values survive in this model until power is lost
}

TEST_CASE("devicenet master: seed 000 §5.1 example 1 layout needs fragmented I/O both ways",
          "[devicenet][master]") {
  devicenet::IoLayout l;
  l.direct_in = l.direct_out1 = l.direct_out2 = true;
  l.masters = {true, true, true, true};
  Rig rig(l, {true, true, true, true});
  REQUIRE(rig.master.connect().ok());
  auto r = rig.master.command({false, false, true, false}, 0x2B, 2048);  // Set Curve Amplitude, C
  REQUIRE(r.ok());
  CHECK(rig.controller.value(Motor::C, 0x2A) == 2048);
  auto status = rig.master.command({}, 0x02, 0);  // Get Status Low Word
  REQUIRE(status.ok());
  CHECK((*status & 0x0003) == 0x0003);  // INIT Done, RUN State
}

namespace {

constexpr std::array<bool, 4> kMotorB{false, true, false, false};

// The polls (Group 2 master I/O poll to MAC 3Fh, identifier 5FDh) whose
// Addressed In word 1 is `word`: the default layout sends the Control Word
// and then word 1 low byte first.
std::size_t polls_with(const std::vector<std::string>& trace, std::uint16_t word) {
  char prefix[40];
  std::snprintf(prefix, sizeof prefix, "TX 5FD [6] 00 00 %02X %02X ", word & 0xFF, word >> 8);
  std::size_t n = 0;
  for (const auto& line : trace)
    if (line.rfind(prefix, 0) == 0) ++n;
  return n;
}

}  // namespace

TEST_CASE(
    "devicenet master: seed 000 §5.2 toggle rule: Get Coded Error, then a Get to motor A, then to "
    "motor B, each executed exactly once under each toggle reading",
    "[devicenet][master][toggle]") {
  for (const char* name : {"seed", "get-set-ignore", "module"}) {
    INFO("toggle rule " << name);
    Rig rig({}, {true, true, false, false}, *sim::parse_toggle_rule(name));
    rig.controller.set_value(Motor::A, 0x24, 11);
    rig.controller.set_value(Motor::B, 0x24, 22);
    REQUIRE(rig.master.connect().ok());
    REQUIRE(rig.master.poll({}).ok());  // the status first, so each count below is one command
    auto executed = rig.controller.commands_executed();
    auto coded = rig.master.command({}, 0x0A, 0);  // Get Coded Error
    REQUIRE(coded.ok());
    CHECK(*coded == 0);
    CHECK(rig.controller.commands_executed() == executed + 1);
    executed = rig.controller.commands_executed();
    auto a = rig.master.command(kMotorA, 0x24, 0);  // Get (Rise) Curve Number
    REQUIRE(a.ok());
    CHECK(*a == 11);
    CHECK(rig.controller.commands_executed() == executed + 1);
    executed = rig.controller.commands_executed();
    auto b = rig.master.command(kMotorB, 0x24, 0);
    REQUIRE(b.ok());
    CHECK(*b == 22);
    CHECK(rig.controller.commands_executed() == executed + 1);
    executed = rig.controller.commands_executed();
    auto again = rig.master.command(kMotorA, 0x24, 0);  // the same Get once more runs again
    REQUIRE(again.ok());
    CHECK(*again == 11);
    CHECK(rig.controller.commands_executed() == executed + 1);
  }
}

TEST_CASE(
    "devicenet master: seed 000 §5.2 toggle rule: a motor command carries the inverse of that "
    "motor's Command Toggle, whatever the controller-level toggle",
    "[devicenet][master][toggle]") {
  Rig rig({}, {true, true, false, false});
  REQUIRE(rig.master.connect().ok());
  REQUIRE(rig.master.command({}, 0x0A, 0).ok());  // controller toggle now 1
  REQUIRE(rig.master.command(kMotorA, 0x25, 5).ok());
  REQUIRE(rig.master.command(kMotorA, 0x25, 6).ok());  // motor A's toggle back to 0
  REQUIRE(rig.master.command(kMotorB, 0x25, 7).ok());
  CHECK(rig.controller.value(Motor::A, 0x24) == 6);
  CHECK(rig.controller.value(Motor::B, 0x24) == 7);
  // 0Ah with toggle 1; 25h to A with 1 (A's Command Toggle was 0), then 0;
  // 25h to B with 1 (B's was 0). Each in one poll: none was taken for a repeat.
  CHECK(polls_with(rig.trace, 0x008A) == 1);
  CHECK(polls_with(rig.trace, 0x10A5) == 1);
  CHECK(polls_with(rig.trace, 0x1025) == 1);
  CHECK(polls_with(rig.trace, 0x20A5) == 1);
  CHECK_FALSE(rig.master.last_status().command_toggle(Motor::A));
  CHECK(rig.master.last_status().command_toggle(Motor::B));
}

TEST_CASE(
    "devicenet master: a Get whose echo stays stale is sent once more with the toggle flipped",
    "[devicenet][master][toggle]") {
  // One toggle for the whole module: after 0Ah with toggle 1, the Get to
  // motor A carries 1 too (A's Command Toggle is 0), which this controller
  // takes for a repeat.
  Rig rig({}, {true, true, false, false}, sim::ToggleRule::module_wide);
  rig.controller.set_value(Motor::A, 0x24, 42);
  REQUIRE(rig.master.connect().ok());
  REQUIRE(rig.master.command({}, 0x0A, 0).ok());
  const auto executed = rig.controller.commands_executed();
  auto r = rig.master.command(kMotorA, 0x24, 0);
  REQUIRE(r.ok());
  CHECK(*r == 42);
  CHECK(rig.controller.commands_executed() == executed + 1);
  CHECK(polls_with(rig.trace, 0x10A4) == devicenet::Master::kStalePolls);
  CHECK(polls_with(rig.trace, 0x1024) == 1);
  CHECK_FALSE(rig.master.last_status().command_toggle(Motor::A));
}

TEST_CASE("devicenet master: a motion command whose echo stays stale is never sent again",
          "[devicenet][master][toggle]") {
  Rig rig({}, {true, true, false, false}, sim::ToggleRule::module_wide);
  REQUIRE(rig.master.connect().ok());
  REQUIRE(rig.master.command({}, 0x0A, 0).ok());
  const auto executed = rig.controller.commands_executed();
  auto r = rig.master.command(kMotorA, 0x20, 3);  // Start Curve 3 on motor A
  REQUIRE_FALSE(r.ok());
  CHECK(r.error().code == make_error_code(Errc::timeout));
  CHECK(r.error().message ==
        "command 20h to DeviceNet MAC ID 63: the Addressed Out echo did not show it after 50 "
        "polls");
  CHECK(polls_with(rig.trace, 0x10A0) == 50);
  CHECK(polls_with(rig.trace, 0x1020) == 0);
  CHECK(rig.controller.commands_executed() == executed);
  CHECK(rig.controller.curves_started() == 0);
}

TEST_CASE(
    "devicenet master: seed 000 §5.2 Start Curve runs once per command under the seed's rule, "
    "with or without Get/Set ignoring the toggle",
    "[devicenet][master][toggle]") {
  for (const char* name : {"seed", "get-set-ignore"}) {
    INFO("toggle rule " << name);
    Rig rig({}, {true, true, false, false}, *sim::parse_toggle_rule(name));
    REQUIRE(rig.master.connect().ok());
    REQUIRE(rig.master.command({}, 0x0A, 0).ok());
    rig.controller.drop_poll_responses(2);  // a lost response: the same poll again
    REQUIRE(rig.master.command(kMotorB, 0x20, 3).ok());
    CHECK(rig.controller.curves_started() == 1);
    REQUIRE(rig.master.command(kMotorB, 0x20, 3).ok());  // the same curve again: a new start
    CHECK(rig.controller.curves_started() == 2);
    REQUIRE(rig.master.command(kMotorA, 0x22, 4).ok());
    CHECK(rig.controller.curves_started() == 3);
  }
}

namespace {

std::size_t polls(const std::vector<std::string>& trace) {
  std::size_t n = 0;
  for (const auto& line : trace)
    if (line.rfind("TX 5FD ", 0) == 0) ++n;
  return n;
}

constexpr const char* kAbsentReadings[] = {"coded-error",   "coded-error-8110", "no-toggle",
                                           "error-no-echo", "echo-only",        "ignore"};

}  // namespace

TEST_CASE(
    "devicenet master: seed 000 §5.2 a command for a motor the controller does not have is "
    "recognised, not waited for, under each toggle and absent-motor reading",
    "[devicenet][master][absent]") {
  for (const char* rule : {"seed", "get-set-ignore", "module"}) {
    for (const char* absent : kAbsentReadings) {
      INFO("toggle rule " << rule << ", absent motor " << absent);
      Rig rig({}, {true, false, false, false}, *sim::parse_toggle_rule(rule),
              *sim::parse_absent_motor(absent));
      rig.controller.set_value(Motor::A, 0x24, 11);
      REQUIRE(rig.master.connect().ok());
      REQUIRE(rig.master.command({}, 0x0A, 0).ok());
      REQUIRE(rig.master.command(kMotorA, 0x24, 0).ok());
      const auto before = polls(rig.trace);
      auto b = rig.master.command(kMotorB, 0x24, 0);  // Get (Rise) Curve Number, motor B
      REQUIRE_FALSE(b.ok());
      CHECK(b.error().code == make_error_code(Errc::drive_refused));
      const auto code = rig.master.last_coded_error();
      CHECK((code == 0x8111 || code == 0x8110 || rig.master.last_not_taken()));
      // Recognised: at most the stale polls, the resend's, and the 02h
      // (with its own resend) that follows; never the 50 of a time-out.
      const auto used = polls(rig.trace) - before;
      CHECK(used <= 4 * devicenet::Master::kStalePolls + 4);
      CHECK(used < static_cast<std::size_t>(devicenet::Master::kPollsForEcho));
      // Motor A still answers, and no error is left pending.
      auto a = rig.master.command(kMotorA, 0x24, 0);
      REQUIRE(a.ok());
      CHECK(*a == 11);
      CHECK_FALSE(rig.master.last_status().error_pending());
    }
  }
}

TEST_CASE("devicenet master: what a command not taken by an absent motor says",
          "[devicenet][master][absent]") {
  {
    Rig rig({}, {true, false, false, false}, sim::ToggleRule::seed, sim::AbsentMotor::ignore);
    REQUIRE(rig.master.connect().ok());
    auto r = rig.master.command(kMotorB, 0x24, 0);
    REQUIRE_FALSE(r.ok());
    CHECK(rig.master.last_not_taken());
    CHECK(rig.master.last_coded_error() == 0);
    CHECK(r.error().message ==
          "command 24h to motor B of DeviceNet MAC ID 63 was not taken: the Addressed Out echo "
          "kept showing the previous command with either toggle, and the controller took the "
          "next command (02h) instead; motor B is probably not a master drive of this "
          "controller");
    // The Get was sent with both toggles, kStalePolls polls each, then 02h once.
    CHECK(polls_with(rig.trace, 0x20A4) == devicenet::Master::kStalePolls);
    CHECK(polls_with(rig.trace, 0x2024) == devicenet::Master::kStalePolls);
    CHECK(polls_with(rig.trace, 0x0082) == 1);
  }
  {
    Rig rig({}, {true, false, false, false}, sim::ToggleRule::seed, sim::AbsentMotor::echo_only);
    REQUIRE(rig.master.connect().ok());
    auto r = rig.master.command(kMotorB, 0x24, 0);
    REQUIRE_FALSE(r.ok());
    CHECK(rig.master.last_not_taken());
    CHECK(r.error().message ==
          "command 24h to motor B of DeviceNet MAC ID 63 was not taken: the Addressed Out echo "
          "shows it, but motor B's Command Toggle did not follow (seed 000 §5.1: \"Actual state "
          "of the command toggle bit\"); motor B is probably not a master drive of this "
          "controller");
  }
  for (auto absent : {sim::AbsentMotor::no_toggle, sim::AbsentMotor::error_no_echo}) {
    Rig rig({}, {true, false, false, false}, sim::ToggleRule::seed, absent);
    REQUIRE(rig.master.connect().ok());
    auto r = rig.master.command(kMotorB, 0x24, 0);
    REQUIRE_FALSE(r.ok());
    CHECK_FALSE(rig.master.last_not_taken());
    CHECK(rig.master.last_coded_error() == 0x8111);
    CHECK(r.error().message ==
          "command 24h to DeviceNet MAC ID 63: the controller reports an error, coded error "
          "8111h Drive not master");
  }
}

}  // namespace devicenet_test_master
