// CAN frames and the slcan (Lawicel ASCII) encoding (lib/can/frame.cpp,
// docs/can.md).
#include <catch2/catch.hpp>
#include <variant>

#include "can/frame.hpp"

// This file's own namespace: the test binary is a unity build (tests/CMakeLists.txt).
namespace can_test_frame {

using namespace lmcfg;

namespace {

Bytes bytes(std::string_view s) { return Bytes(s.begin(), s.end()); }

}  // namespace

TEST_CASE("can: slcan encodes standard, extended and remote frames", "[can]") {
  const std::uint8_t ab[] = {0xAA, 0xBB};
  CHECK(can::slcan::encode(can::Frame::standard(0x123, ab)) == "t1232AABB\r");
  // A DeviceNet Group 2 frame: ID 10 MMMMMM 110 = Allocate_Master/Slave to MAC 05h.
  const std::uint8_t alloc[] = {0x00, 0x4B, 0x03, 0x01, 0x03, 0x00};
  CHECK(can::slcan::encode(can::Frame::standard(0x42E, alloc)) == "t42E6004B03010300\r");
  can::Frame ext;
  ext.id = 0x1ABCDEF0;
  ext.extended = true;
  CHECK(can::slcan::encode(ext) == "T1ABCDEF00\r");
  can::Frame rtr;
  rtr.id = 0x7FF;
  rtr.rtr = true;
  rtr.len = 2;
  CHECK(can::slcan::encode(rtr) == "r7FF2\r");
  CHECK(can::describe(can::Frame::standard(0x42E, alloc)) == "42E [6] 00 4B 03 01 03 00");
  CHECK(can::describe(ext) == "1ABCDEF0x [0]");
  CHECK(can::describe(rtr) == "7FF [2] RTR");
}

TEST_CASE("can: frames out of range are refused with the reason", "[can]") {
  can::Frame f;
  f.id = 0x800;
  CHECK(can::validate(f).error().message == "CAN identifier 800h does not fit 11 bits");
  f.id = 0x10;
  f.len = 9;
  CHECK(can::validate(f).error().message == "CAN frame length 9 is more than 8 bytes");
}

TEST_CASE("can: slcan bit rates, DeviceNet's three and no others by mistake", "[can]") {
  CHECK(can::slcan::bitrate_command(125000).value() == "S4\r");
  CHECK(can::slcan::bitrate_command(250000).value() == "S5\r");
  CHECK(can::slcan::bitrate_command(500000).value() == "S6\r");
  CHECK(can::slcan::bitrate_command(1000000).value() == "S8\r");
  CHECK(can::slcan::bitrate_command(125).error().message ==
        "CAN bit rate 125 is not one slcan can set (DeviceNet: 125000, 250000 or 500000)");
}

TEST_CASE("can: the slcan decoder splits frames, acknowledgements, bells and junk across reads",
          "[can]") {
  can::slcan::Decoder d;
  auto first = d.feed(bytes("t1232AA"));
  CHECK(first.empty());
  auto rest = d.feed(bytes("BB\rz\r\a\r\nt12321122ABCD\rhello\rt12"));
  REQUIRE(rest.size() == 6);
  CHECK(std::get<can::Frame>(rest[0]) == can::Frame::standard(0x123, bytes("\xAA\xBB")));
  CHECK(std::get<can::slcan::Ack>(rest[1]).kind == 'z');
  CHECK(std::holds_alternative<can::slcan::Bell>(rest[2]));
  CHECK(std::get<can::slcan::Ack>(rest[3]).kind == 0);  // CR, then LF ignored
  CHECK(std::get<can::Frame>(rest[4]).len == 2);        // time stamp ABCD ignored
  CHECK(std::get<can::slcan::Unknown>(rest[5]).line == "hello");
  CHECK_FALSE(can::slcan::parse_frame_line("t1239"));       // length 9
  CHECK_FALSE(can::slcan::parse_frame_line("t1232AA"));     // data short
  CHECK_FALSE(can::slcan::parse_frame_line("t1232AABBC"));  // stray digit
  CHECK_FALSE(can::slcan::parse_frame_line("t8002AABB"));   // beyond 11 bits
}

}  // namespace can_test_frame
