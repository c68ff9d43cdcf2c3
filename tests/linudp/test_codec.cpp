// LinUDP V2 framing (lib/linudp/codec.*) against byte examples: the telegrams
// of the C1250 notes' mock drive (served over UDP by the project) and their
// tests' exact bytes, LinUDP V2 §4.4's offsets, §7's count rule, p14's codes.
#include <catch2/catch.hpp>

#include "linudp/codec.hpp"

// This file's own namespace: the test binary is a unity build (tests/CMakeLists.txt).
namespace linudp_test_codec {

using namespace lmcfg;
using namespace lmcfg::linudp;

namespace {
Bytes hexb(const char* text) { return *from_hex(text); }
RtcBlock rtc(std::uint8_t count, std::uint8_t id, std::uint16_t w2, std::uint32_t value = 0) {
  RtcBlock r;
  r.count = count;
  r.id = id;
  r.w2 = w2;
  r.set_value(value);
  return r;
}
}  // namespace

TEST_CASE("LinUDP C1250 notes mock: write RAM request bytes", "[linudp][codec][golden]") {
  // "write RAM TX 04000000 ff010000 | 01 13 5a14 a0860100 (count 1, 13h, UPID 145Ah, 100000)"
  CHECK(encode_request(rtc(1, 0x13, 0x145A, 100000)) ==
        hexb("04000000 ff010000 01 13 5a14 a0860100"));
}

TEST_CASE("LinUDP C1250 notes mock: read RAM, modified list, CT presence requests",
          "[linudp][codec][golden]") {
  CHECK(encode_request(rtc(2, 0x11, 0x145A)) == hexb("04000000 ff010000 02 11 5a14 00000000"));
  CHECK(encode_request(rtc(3, 0x22, 0)) == hexb("04000000 ff010000 03 22 0000 00000000"));
  CHECK(encode_request(rtc(4, 0x23, 0)) == hexb("04000000 ff010000 04 23 0000 00000000"));
  CHECK(encode_request(rtc(5, 0x87, 0)) == hexb("04000000 ff010000 05 87 0000 00000000"));
}

TEST_CASE("LinUDP C1250 notes test: CT write 83h puts the size 64 in word 3",
          "[linudp][codec][golden]") {
  // "for 83h with entry 1 and size 64, bytes 12-15 = 40000000, bytes 10-11 = 0100"
  RtcBlock r = rtc(1, 0x83, 1);
  r.w3 = 64;
  const Bytes b = encode_request(r);
  REQUIRE(b.size() == 16);
  CHECK(Bytes(b.begin() + 10, b.begin() + 12) == hexb("0100"));
  CHECK(Bytes(b.begin() + 12, b.begin() + 16) == hexb("40000000"));
}

TEST_CASE("LinUDP C1250 notes mock: status reply of 26 bytes decoded from its definition",
          "[linudp][codec][golden]") {
  // "RX (26 B) 00000000 7f000000 0000 0001 a0860100 a0860100 6400 0000 0000"
  auto r = decode_response(hexb("00000000 7f000000 0000 0001 a0860100 a0860100 6400 0000 0000"));
  REQUIRE(r.ok());
  CHECK(r->response_def == 0x7F);
  CHECK(r->status_word == 0x0000);
  CHECK(r->state_var == 0x0100);
  CHECK(r->actual_pos == 100000);
  CHECK(r->demand_pos == 100000);
  CHECK(r->current == 100);
  CHECK(r->warn_word == 0);
  CHECK(r->error_code == 0);
  CHECK_FALSE(r->monitoring);
  CHECK_FALSE(r->rtc);  // request bit 2 not echoed: no RTC part (LinUDP V2 §4.4.2)
  CHECK_FALSE(r->all_zero);
}

TEST_CASE(
    "LinUDP V2 §4.4.2: with response definition 1FFh the RTC reply sits at 42-49, padded "
    "to 64",
    "[linudp][codec][golden]") {
  Response r;
  r.request_def = req::rtc;
  r.response_def = resp::all;
  r.status_word = 0x4C37;
  r.rtc = rtc(5, 0x00, 0, 0xFFFFFFFF);  // the mock's "CT pres 0 ... RX 05 00 0000 ffffffff"
  const Bytes b = encode_response(r);
  REQUIRE(b.size() == 64);
  CHECK(get_u16le(b, 8) == 0x4C37);
  CHECK(Bytes(b.begin() + 42, b.begin() + 50) == hexb("05 00 0000 ffffffff"));
  CHECK(std::all_of(b.begin() + 50, b.end(), [](std::uint8_t x) { return x == 0; }));
  auto back = decode_response(b);
  REQUIRE(back.ok());
  REQUIRE(back->rtc);
  CHECK(back->rtc->count == 5);
  CHECK(back->rtc->value() == 0xFFFFFFFF);
}

TEST_CASE("LinUDP V2 §4.4.1 and the mock: a combined telegram (reqdef 7) locates CW, MC and RTC",
          "[linudp][codec][golden]") {
  // "combined TX 07000000 ff010000 0000 <32 B zeros> | 06 11 5a14 00000000"
  Bytes b = hexb("07000000 ff010000 0000");
  b.resize(b.size() + 32, 0);
  const Bytes tail = hexb("06 11 5a14 00000000");
  b.insert(b.end(), tail.begin(), tail.end());
  REQUIRE(b.size() == 50);
  auto r = decode_request(b);
  REQUIRE(r.ok());
  CHECK(r->control_word == 0x0000);
  CHECK(r->has_mc);
  REQUIRE(r->rtc);
  CHECK(r->rtc->count == 6);
  CHECK(r->rtc->id == 0x11);
  CHECK(r->rtc->w2 == 0x145A);
}

TEST_CASE("LinUDP C1250 notes test: control word telegrams carry no RTC part",
          "[linudp][codec][golden]") {
  // "CW telegrams 01000000 01000000 0F00 (enable)": what lmcfg never sends
  auto r = decode_request(hexb("01000000 01000000 0F00"));
  REQUIRE(r.ok());
  CHECK(r->control_word == 0x000F);
  CHECK_FALSE(r->rtc);
}

TEST_CASE("LinUDP V2 §4.4.1: every request lmcfg encodes is RTC only (reqdef 04h)",
          "[linudp][codec]") {
  for (int id = 0; id < 256; ++id) {
    const Bytes b = encode_request(rtc(7, static_cast<std::uint8_t>(id), 0x1234, 0xDEADBEEF));
    CHECK(b.size() == 16);
    CHECK(get_u32le(b, 0) == req::rtc);
  }
}

TEST_CASE("LinUDP C1250 notes: an all-zero datagram is recognised", "[linudp][codec]") {
  auto r = decode_response(Bytes(64, 0));
  REQUIRE(r.ok());
  CHECK(r->all_zero);
  CHECK_FALSE(r->rtc);
}

TEST_CASE("LinUDP V2 §4.4.2: a datagram cut short names the missing part", "[linudp][codec]") {
  auto r = decode_response(hexb("04000000 ff010000 0000"));
  REQUIRE_FALSE(r.ok());
  CHECK(r.error().message ==
        "LinUDP datagram of 10 bytes ends before its state var (needs 12 bytes, LinUDP V2 §4.4)");
}

TEST_CASE("LinUDP V2 §7 (15 and backward steps open): counts run 2..14, forward, never the echo",
          "[linudp][codec]") {
  Counter c;
  std::vector<int> seen;
  for (int i = 0; i < 15; ++i) seen.push_back(c.next());
  CHECK(seen == std::vector<int>{2, 3, 4, 5, 6, 7, 8, 9, 10, 11, 12, 13, 14, 2, 3});
  Counter d;
  CHECK(d.next(std::uint8_t{2}) == 3);  // the drive holds 2: skip it
  d.seed(14);
  CHECK(d.next() == 2);
  d.seed(0);  // after a restart (count 0, LinUDP DLL)
  CHECK(d.next() == 2);
}

TEST_CASE("LinUDP V2 p14: status codes and their meaning", "[linudp][codec]") {
  CHECK(std::string(status_text(0xC0)) == "UPID error");
  CHECK(std::string(status_text(0xC6)) == "end of UPID list");
  CHECK(std::string(status_text(0xD4)) == "curve already defined or not present");
  CHECK(status_text(0xD7) == nullptr);  // not in LinUDP V2 p14: D7h is LinRS 3V27 p32's
  CHECK(is_busy(0x02));
  CHECK(is_busy(0x05));
  CHECK_FALSE(is_busy(0x04));
  CHECK(cmd_name(0x80) == "save command table to flash (80h)");
  CHECK(is_write_command(0x12));
  CHECK_FALSE(is_write_command(0x10));
}

}  // namespace linudp_test_codec
