// The DeviceNet controllers' polled I/O (lib/devicenet/command.cpp, DeviceNet
// §5.1 and §5.2): command words, status words, the toggle rule, the module
// layouts of the seed's two examples, the coded errors.
#include <catch2/catch.hpp>

#include "devicenet/catalogue.hpp"
#include "devicenet/command.hpp"

// This file's own namespace: the test binary is a unity build (tests/CMakeLists.txt).
namespace devicenet_test_command {

using namespace lmcfg;
using devicenet::Motor;

TEST_CASE("seed000 §5.2: command words of Table 5-1 as the bit tables draw them", "[devicenet]") {
  devicenet::CommandWord start;  // Start Curve (20h): Motor A sel, T, 0100000
  start.id = 0x20;
  start.toggle = true;
  start.motors[static_cast<int>(Motor::A)] = true;
  CHECK(start.encode() == 0x10A0);
  CHECK(devicenet::CommandWord::decode(0x10A0) == start);
  devicenet::CommandWord status;  // Get Status Low Word (02h), no motor, X = 0
  status.id = 0x02;
  CHECK(status.encode() == 0x0002);
  devicenet::CommandWord all;  // Set Position Setpoint (11h) for D, C, B, A
  all.id = 0x11;
  all.motors = {true, true, true, true};
  CHECK(all.encode() == 0xF011);
  CHECK(devicenet::CommandWord::decode(0xF091).toggle);
  CHECK(devicenet::CommandWord::decode(0xF091).id == 0x11);
}

TEST_CASE("seed000 §5.1: Status Out bits by name", "[devicenet]") {
  devicenet::Status s;
  s.low = 0x1102;   // In Position A, Curve Done A, RUN State
  s.high = 0x0089;  // Motor B Command Toggle, Motor A Command Toggle + Following Error
  CHECK(s.run_state());
  CHECK(s.in_position(Motor::A));
  CHECK_FALSE(s.in_position(Motor::B));
  CHECK(s.command_toggle(Motor::A));
  CHECK(s.command_toggle(Motor::B));
  CHECK(s.following_error(Motor::A));
  CHECK(s.names() == std::vector<std::string>{"RUN State", "Curve Done A", "In Position Motor A",
                                              "Motor A Following Error", "Motor A Command Toggle",
                                              "Motor B Command Toggle"});
}

TEST_CASE(
    "seed000 §5.2 Start Curve: the toggle sent is the inverse of the motor's Command "
    "Toggle, and the command has run when the status shows it",
    "[devicenet]") {
  devicenet::Status before;
  before.high = 0x0008;  // Motor A Command Toggle set
  const bool t = devicenet::toggle_to_send(before, Motor::A);
  CHECK_FALSE(t);
  CHECK_FALSE(devicenet::command_done(before, Motor::A, t));
  devicenet::Status after;
  after.high = 0x0000;
  CHECK(devicenet::command_done(after, Motor::A, t));
  CHECK(devicenet::toggle_to_send(after, Motor::C));  // C's toggle clear: send 1
}

TEST_CASE(
    "seed000 §5.2 bit definitions: bit 7 is the toggle for 13h, 15h, 19h, 20h and 22h, X for the "
    "others",
    "[devicenet][toggle]") {
  // Drawn "Toggle" (Increment Position Setpoint 13h) or "T" (Move Home 15h,
  // Set Actual Position 19h, Start Curve 20h, Start Curve Incremental 22h).
  for (int id : {0x13, 0x15, 0x19, 0x20, 0x22}) {
    INFO(id);
    CHECK(devicenet::toggle_command(static_cast<std::uint8_t>(id)));
  }
  // Drawn "X": No Command, Get Coded Error, Reset Coded Error, the position
  // setpoints, Get Actual Position, Start Curve (Incremental) Waiting for
  // Trigger, the curve number Get/Set.
  for (int id : {0x00, 0x0A, 0x0B, 0x10, 0x11, 0x12, 0x14, 0x18, 0x21, 0x23, 0x24, 0x25}) {
    INFO(id);
    CHECK_FALSE(devicenet::toggle_command(static_cast<std::uint8_t>(id)));
  }
}

TEST_CASE("seed000 §5.1 example 1: four master drives, every module", "[devicenet]") {
  devicenet::IoLayout l;
  l.direct_in = l.direct_out1 = l.direct_out2 = true;
  l.masters = {true, true, true, true};
  CHECK(l.command_size() == 22);   // words 1..11
  CHECK(l.response_size() == 24);  // words 1..12
  devicenet::PollCommand c;
  c.control = 0x0002;  // RUN Request
  c.addressed.id = 0x02;
  c.direct[1].id = 0x11;  // motor B: Set Position Setpoint
  c.direct_value[1] = 0x1234;
  const Bytes cmd = devicenet::encode_command(l, c);
  REQUIRE(cmd.size() == 22);
  CHECK(cmd[0] == 0x02);                      // word 1 Control Word, low byte first
  CHECK(cmd[2] == 0x02);                      // word 2 Addressed Command ID
  CHECK((cmd[10] | cmd[11] << 8) == 0x0011);  // word 6 Direct Command ID Motor B
  CHECK((cmd[12] | cmd[13] << 8) == 0x1234);  // word 7 Direct Command Value Motor B
  Bytes resp(24, 0);
  resp[0] = 0x02;   // word 1 Status Low: RUN State
  resp[4] = 0x02;   // word 3 Echo Addressed Command ID
  resp[6] = 0x2A;   // word 4 Addressed Command Value Response
  resp[14] = 0x07;  // word 8 Direct Out 2 Response Motor B
  auto r = devicenet::decode_response(l, resp);
  REQUIRE(r.ok());
  CHECK(r->status.run_state());
  CHECK(r->addressed_echo.id == 0x02);
  CHECK(r->addressed_value == 0x2A);
  CHECK(r->direct_out2[1] == 7);
}

TEST_CASE(
    "seed000 §5.1 example 2: master drives A and C, Control, Direct In, Status and Direct "
    "Out 1",
    "[devicenet]") {
  devicenet::IoLayout l;
  l.addressed_in = l.addressed_out = false;
  l.direct_in = l.direct_out1 = true;
  l.masters = {true, false, true, false};
  CHECK(l.command_size() == 10);  // 5 words
  CHECK(l.response_size() == 8);  // 4 words
  Bytes resp = {0x00, 0x00, 0x00, 0x00, 0x34, 0x12, 0x78, 0x56};
  auto r = devicenet::decode_response(l, resp);
  REQUIRE(r.ok());
  CHECK(r->direct_out1[0] == 0x1234);  // word 3: Direct Out 1 Response Motor A
  CHECK(r->direct_out1[2] == 0x5678);  // word 4: Direct Out 1 Response Motor C
}

TEST_CASE(
    "devicenet: the default modules make 6 bytes out and 8 back, a response of another "
    "size is refused with both sizes",
    "[devicenet]") {
  devicenet::IoLayout l;
  CHECK(l.command_size() == 6);
  CHECK(l.response_size() == 8);
  auto r = devicenet::decode_response(l, Bytes(6, 0));
  REQUIRE_FALSE(r.ok());
  CHECK(r.error().code == make_error_code(Errc::frame_short));
  CHECK(r.error().message == "poll response of 6 byte(s); the configured modules make 8");
}

TEST_CASE("seed000 §5.2 Get Coded Error: the application errors' texts", "[devicenet]") {
  CHECK(devicenet::coded_error_text(0x8112) == "Drive not in serial mode");
  CHECK(devicenet::coded_error_text(0x8148) == "CAN BOFF error");
  CHECK(devicenet::coded_error_text(0x0001).empty());
}

}  // namespace devicenet_test_command
