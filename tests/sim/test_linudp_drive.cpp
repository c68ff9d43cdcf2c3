// sim::LinudpDrive (lib/sim/linudp_drive.*): the count rule of
// LinUDP V2 §7 as a drive keeps it, the reply layout of §4.4.2, and the
// field options' names.
#include <catch2/catch.hpp>

#include "e2e_support.hpp"
#include "sim/linudp_drive.hpp"

// This file's own namespace: the test binary is a unity build (tests/CMakeLists.txt).
namespace sim_test_linudp_drive {

using namespace lmcfg;
using linudp::RtcBlock;

namespace {
linudp::Response ask(sim::LinudpDrive& d, std::uint8_t count, std::uint8_t id, std::uint16_t w2,
                     std::uint32_t value = 0, std::int64_t now = 0) {
  RtcBlock r;
  r.count = count;
  r.id = id;
  r.w2 = w2;
  r.set_value(value);
  auto answers = d.receive(linudp::encode_request(r), now);
  REQUIRE(answers.size() == 1);
  CHECK(answers[0].bytes.size() == 64);  // LinUDP V2 §4.4.2: padded to 64
  auto resp = linudp::decode_response(answers[0].bytes);
  REQUIRE(resp.ok());
  REQUIRE(resp->rtc);
  return *resp;
}
}  // namespace

TEST_CASE("LinUDP sim V2 §7: a command runs once per count, a resend repeats its reply",
          "[linudp][sim]") {
  auto drive = test::load_sim_drive("commissioned-axis.json");
  sim::LinudpDrive d(drive);
  const auto upid = drive->state().params.begin()->first;
  auto w = ask(d, 3, 0x13, upid, 1234);  // write RAM
  CHECK(w.rtc->id == 0x00);
  CHECK(w.rtc->count == 3);
  drive->state().params[upid].ram = 99;      // changed behind the drive's back
  auto again = ask(d, 3, 0x13, upid, 1234);  // the same count: not executed again
  CHECK(again.rtc->id == 0x00);
  CHECK(drive->state().params[upid].ram == 99);
  CHECK(d.stats().commands == 1);
  CHECK(d.stats().resends == 1);
  auto r = ask(d, 4, 0x11, upid);  // a new count: read RAM
  CHECK(r.rtc->value() == 99);
  CHECK(r.request_def == linudp::req::rtc);  // echoed (C1250 notes)
  CHECK(r.response_def == linudp::resp::all);
}

TEST_CASE("LinUDP sim V2 §4.4.1: the reply to a control word telegram is counted as motion",
          "[linudp][sim]") {
  sim::LinudpDrive d(test::load_sim_drive("commissioned-axis.json"));
  auto answers = d.receive(*from_hex("01000000 01000000 0F00"), 0);
  CHECK(d.stats().motion_telegrams == 1);
  REQUIRE(answers.size() == 1);
  auto resp = linudp::decode_response(answers[0].bytes);
  REQUIRE(resp.ok());
  CHECK_FALSE(resp->rtc);
}

TEST_CASE("LinUDP sim V2 p13-p16: an absent curve is D4h, the end of a list C6h", "[linudp][sim]") {
  sim::LinudpDrive d(test::load_sim_drive("commissioned-axis.json"));
  CHECK(ask(d, 2, 0x60, 99).rtc->id == 0xD4);
  CHECK(ask(d, 3, 0x23, 0).rtc->id == 0xC5);  // next without start
  CHECK(ask(d, 4, 0x22, 0x3000).rtc->id == 0x00);
  std::uint8_t st = 0;
  for (std::uint8_t c = 5; c < 14 && st != 0xC6; ++c) st = ask(d, c, 0x23, 0).rtc->id;
  CHECK(st == 0xC6);
}

TEST_CASE("LinUDP sim: --linudp-field names and values", "[linudp][sim]") {
  sim::LinudpField f;
  REQUIRE(sim::set_field(f, "unacknowledged_saves").ok());
  REQUIRE(sim::set_field(f, "save_s=75").ok());
  REQUIRE(sim::set_field(f, "running_status=0").ok());
  CHECK(f.unacknowledged_saves);
  CHECK(f.save_us == 75'000'000);
  CHECK(f.running_status == 0);
  CHECK(sim::field_words(f) ==
        std::vector<std::string>{"unacknowledged_saves=true", "save_s=75", "running_status=0"});
  auto bad = sim::set_field(f, "running_status=7");
  REQUIRE_FALSE(bad.ok());
  CHECK(bad.error().message == "--linudp-field 'running_status=7': 2, 5 or 0 expected");
  auto unknown = sim::set_field(f, "fast_saves");
  REQUIRE_FALSE(unknown.ok());
  CHECK(unknown.error().message.rfind("--linudp-field 'fast_saves': unknown name; one of:\n", 0) ==
        0);
}

}  // namespace sim_test_linudp_drive
