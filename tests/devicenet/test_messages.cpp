// DeviceNet messages of the Predefined Master/Slave Connection Set
// (lib/devicenet/messages). Seed 000 does not give this layer; the golden
// vectors are the worked examples of vendors' published DeviceNet manuals:
//   [ICP-8124] ICP DAS CAN-8124/8224/8424 User Manual v2.0 (2007) §7.2.2
//              "How to apply the Poll IO connection" (slave 09h, master 0Ah)
//   [ICP-7242] ICP DAS I-7242D User's Manual v1.1 (2006) §7.2.2
//   [RA-160]   Rockwell Automation 160-DN2 User Manual (0160-5.18) App. B
//              "DeviceNet Message Types" (identifier bit patterns)
//   [MKS]      MKS Baratron DMA manual App. D "I/O Poll Messaging" (MAC 05h)
#include <catch2/catch.hpp>

#include "devicenet/messages.hpp"

// This file's own namespace: the test binary is a unity build (tests/CMakeLists.txt).
namespace devicenet_test_messages {

using namespace lmcfg;
using devicenet::Group2;

namespace {
Bytes hex_bytes(std::initializer_list<int> v) {
  Bytes b;
  for (int x : v) b.push_back(static_cast<std::uint8_t>(x));
  return b;
}
}  // namespace

TEST_CASE("DeviceNet identifiers [RA-160] [MKS]", "[devicenet][golden]") {
  CHECK(devicenet::group2_id(0x09, Group2::unconnected_explicit_request) ==
        0x44E);                                                                 // 10 001001 110
  CHECK(devicenet::group2_id(0x09, Group2::slave_explicit_response) == 0x44B);  // 10 001001 011
  CHECK(devicenet::group2_id(0x09, Group2::master_explicit_request) == 0x44C);  // 10 001001 100
  CHECK(devicenet::group2_id(0x05, Group2::master_io_poll) == 0x42D);           // [MKS] 42D
  CHECK(devicenet::group2_id(0x09, Group2::duplicate_mac_check) == 0x44F);      // 10 001001 111
  CHECK(devicenet::group1_id(devicenet::kSlavePollResponse, 0x09) == 0x3C9);    // 01111 001001
  CHECK(devicenet::describe_identifier(0x44E) == "Group 2 MAC 09h unconnected explicit request");
  CHECK(devicenet::describe_identifier(0x3C9) == "Group 1 MAC 09h slave's I/O poll response (Fh)");
}

TEST_CASE(
    "DeviceNet Allocate_Master/Slave_Connection_Set request and response [ICP-8124] "
    "[ICP-7242]",
    "[devicenet][golden]") {
  const auto strobed = devicenet::allocate(
      0x0A, devicenet::kAllocExplicit | devicenet::kAllocPolled | devicenet::kAllocBitStrobe);
  CHECK(strobed.encode() == hex_bytes({0x0A, 0x4B, 0x03, 0x01, 0x07, 0x0A}));
  const auto polled =
      devicenet::allocate(0x0A, devicenet::kAllocExplicit | devicenet::kAllocPolled);
  CHECK(polled.encode() == hex_bytes({0x0A, 0x4B, 0x03, 0x01, 0x03, 0x0A}));
  auto response = devicenet::Explicit::decode(hex_bytes({0x0A, 0xCB, 0x00}));
  REQUIRE(response.ok());
  CHECK(response->response);
  CHECK(response->mac == 0x0A);
  auto body_format = devicenet::response_data(polled, *response);
  REQUIRE(body_format.ok());
  CHECK(*body_format == hex_bytes({0x00}));  // message body format DeviceNet (8/8)
}

TEST_CASE(
    "DeviceNet Set_Attribute_Single of the polled connection's expected packet rate "
    "[ICP-8124]",
    "[devicenet][golden]") {
  const std::uint8_t rate[] = {0x0A, 0x0E};  // 0E0Ah ms, low byte first
  const auto set =
      devicenet::set_attribute(0x0A, devicenet::kConnectionClass, devicenet::kPolledConnection,
                               devicenet::kExpectedPacketRate, rate);
  CHECK(set.encode() == hex_bytes({0x0A, 0x10, 0x05, 0x02, 0x09, 0x0A, 0x0E}));
  auto response = devicenet::Explicit::decode(hex_bytes({0x0A, 0x90, 0x10, 0x0E}));
  REQUIRE(response.ok());
  auto granted = devicenet::response_data(set, *response);
  REQUIRE(granted.ok());
  CHECK(*granted == hex_bytes({0x10, 0x0E}));  // the slave rounds to its timer: 0E10h
}

TEST_CASE("DeviceNet error responses name the service and both codes", "[devicenet]") {
  const auto req = devicenet::allocate(0x0A, devicenet::kAllocExplicit | devicenet::kAllocPolled);
  auto err = devicenet::Explicit::decode(hex_bytes({0x0A, 0x94, 0x0C, 0x01}));
  REQUIRE(err.ok());
  auto r = devicenet::response_data(req, *err);
  REQUIRE_FALSE(r.ok());
  CHECK(r.error().code == make_error_code(Errc::drive_refused));
  CHECK(r.error().message ==
        "error response to Allocate_Master/Slave_Connection_Set 4Bh: general error 0Ch object "
        "state conflict, additional 01h");
  auto other = devicenet::Explicit::decode(hex_bytes({0x0A, 0x8E, 0x01}));
  CHECK(devicenet::response_data(req, *other).error().message ==
        "response to service 0Eh instead of Allocate_Master/Slave_Connection_Set 4Bh");
  CHECK(devicenet::Explicit::decode(hex_bytes({0x0A})).error().message ==
        "explicit message of 1 byte(s): header and service need 2");
}

TEST_CASE(
    "DeviceNet I/O fragmentation: 7 data bytes per frame behind the protocol byte, and "
    "back",
    "[devicenet]") {
  Bytes twelve;
  for (int i = 0; i < 12; ++i) twelve.push_back(static_cast<std::uint8_t>(i));
  auto frames = devicenet::fragment_io(twelve);
  REQUIRE(frames.size() == 2);
  CHECK(frames[0] == hex_bytes({0x00, 0, 1, 2, 3, 4, 5, 6}));  // first, count 0
  CHECK(frames[1] == hex_bytes({0x81, 7, 8, 9, 10, 11}));      // last, count 1
  Bytes twenty(20, 0xEE);
  auto three = devicenet::fragment_io(twenty);
  REQUIRE(three.size() == 3);
  CHECK(three[1][0] == 0x41);  // middle, count 1
  CHECK(three[2][0] == 0x82);  // last, count 2
  CHECK(devicenet::fragment_io(hex_bytes({1, 2, 3, 4, 5, 6, 7, 8})).size() == 1);

  devicenet::IoReassembler r;
  CHECK_FALSE(r.feed(three[0], true).value());
  CHECK_FALSE(r.feed(three[1], true).value());
  CHECK(r.feed(three[2], true).value() == twenty);
  CHECK_FALSE(r.feed(three[0], true).value());
  auto skipped = r.feed(three[2], true);
  REQUIRE_FALSE(skipped.ok());
  CHECK(skipped.error().message == "I/O fragment count 2 out of sequence (expected count 1)");
  CHECK(r.feed(hex_bytes({1, 2}), false).value() == hex_bytes({1, 2}));
}

}  // namespace devicenet_test_messages
