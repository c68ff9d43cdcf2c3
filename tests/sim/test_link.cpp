// The simulated line (lib/sim/link.cpp): the bus of drives that hear every
// telegram, the virtual clock that times each byte on the wire, real-time
// mode, fault injection per exchange and the input buffer.
#include <chrono>

#include "test_sim_harness.hpp"

// This file's own namespace: the test binary is a unity build (tests/CMakeLists.txt).
namespace sim_test_link {

using namespace lmcfg;
using namespace lmcfg::codec;
using lmcfg::test::load_fixture;
using lmcfg::test::SimHarness;

namespace {
constexpr std::uint8_t kId = 0x11;
}  // namespace

TEST_CASE("sim: frames for other MACIDs are ignored, a bus answers only from the addressed drive",
          "[sim]") {
  auto bus = std::make_shared<sim::Bus>();
  auto a = load_fixture("commissioned-axis.json");
  auto b = load_fixture("used-spare.json");
  b.macid = 0x12;
  bus->add(std::make_shared<sim::Drive>(a));
  bus->add(std::make_shared<sim::Drive>(b));
  sim::SimLink link(bus);
  auto ask = [&](std::uint8_t id) {
    REQUIRE(link.write(encode(make_cfg(id, CfgOp::read_rom, 0x13A2)).value()).ok());
    auto r = link.read_some(transport::Millis(100));
    REQUIRE(r.ok());
    return *r;
  };
  auto r11 = decode_id_value(decode(ask(0x11)).value(), 0x50);
  auto r12 = decode_id_value(decode(ask(0x12)).value(), 0x50);
  CHECK(r11->id == 0x11);
  CHECK(r11->value == 40u);
  CHECK(r12->id == 0x12);
  CHECK(r12->value == 25u);
  CHECK(ask(0x13).empty());
  CHECK(bus->drive(0x11)->stats().ignored_other_id == 2);
  CHECK(link.stats().request_telegrams == 3);
  CHECK(link.stats().answer_telegrams == 2);
}

TEST_CASE("sim: virtual clock, 9-byte request + 14-byte answer at 57600 8N1 = 23*10/57600 s + 1 ms",
          "[sim]") {
  auto s = load_fixture("commissioned-axis.json");
  SimHarness h(s);
  CHECK(h.link.byte_time_us() == Approx(10.0 * 1e6 / 57600));
  const auto t0 = h.link.clock().now_ns();
  auto rx = h.exchange(from_hex("01 11 05 02 00 05 A2 13 04").value());
  CHECK(rx.size() == 14);
  const double expected_ns = 23.0 * 10.0 / 57600.0 * 1e9 + 1e6;
  CHECK(static_cast<double>(h.link.clock().now_ns() - t0) == Approx(expected_ns).margin(1.0));
  CHECK(h.link.stats().request_bytes == 9);
  CHECK(h.link.stats().answer_bytes == 14);
  CHECK(h.link.stats().request_telegrams == 1);
  CHECK(h.link.stats().answer_telegrams == 1);
  // 8E2 at 19200: 12 bits per byte.
  s.link = {"", 19200, transport::Parity::even, 2};
  SimHarness h2(s);
  const auto t1 = h2.link.clock().now_ns();
  (void)h2.exchange(from_hex("01 11 05 02 00 05 A2 13 04").value());
  CHECK(static_cast<double>(h2.link.clock().now_ns() - t1) ==
        Approx(23.0 * 12 / 19200 * 1e9 + 1e6).margin(1.0));
}

TEST_CASE("sim: read_some times out on the virtual clock", "[sim]") {
  SimHarness h("commissioned-axis.json");
  const auto t0 = h.link.clock().now_ns();
  auto r = h.link.read_some(transport::Millis(250));
  REQUIRE(r.ok());
  CHECK(r->empty());
  CHECK(h.link.clock().now_ns() - t0 == 250'000'000);
  // An answer that needs longer than the timeout is not delivered yet...
  REQUIRE(h.link.write(encode(make_cfg_default_layer(kId, 1)).value()).ok());
  CHECK(h.link.read_some(transport::Millis(100))->empty());
  // ...but comes later.
  CHECK(h.link.read_some(transport::Millis(2000))->size() == 14);
  CHECK(h.link.stats().read_timeouts == 2);
}

TEST_CASE("sim: real-time mode sleeps for the modelled time", "[sim]") {
  SimHarness h("commissioned-axis.json");
  h.drive->state().timing.turnaround_us = 20'000;
  h.link.set_real_time(true);
  const auto w0 = std::chrono::steady_clock::now();
  CHECK(h.exchange(from_hex("01 11 05 02 00 05 A2 13 04").value()).size() == 14);
  const auto wall = std::chrono::steady_clock::now() - w0;
  CHECK(wall >= std::chrono::milliseconds(20));
}

TEST_CASE("sim: fault injection per exchange", "[sim][sim-faults]") {
  SimHarness h("commissioned-axis.json");
  const Bytes req = encode(make_cfg(kId, CfgOp::read_rom, 0x13A2)).value();
  const Bytes good = h.exchange(req);  // exchange 0
  REQUIRE(good.size() == 14);
  auto& f = h.link.faults();

  SECTION("drop request / drop answer") {
    f.schedule(1, sim::Fault::drop_request());
    f.schedule(2, sim::Fault::drop_answer());
    CHECK(h.exchange(req, 100).empty());
    CHECK(h.exchange(req, 100).empty());
    CHECK(h.exchange(req) == good);
    CHECK(f.counters().dropped_requests == 1);
    CHECK(f.counters().dropped_answers == 1);
    CHECK(h.drive->stats().answers == 3);  // the dropped answer was computed
  }
  SECTION("corrupt / garbage / wrong ID / delay") {
    f.schedule(1, sim::Fault::corrupt(9, 0xFF));
    f.schedule(2, sim::Fault::garbage_burst({0xAA, 0x55}));
    f.schedule(3, sim::Fault::wrong_id(0x33));
    f.schedule(4, sim::Fault::delay(500));
    auto c = h.exchange(req);
    CHECK(c.size() == good.size());
    CHECK(c[9] == (good[9] ^ 0xFF));
    auto g = h.exchange(req);
    REQUIRE(g.size() == good.size() + 2);
    CHECK(g[0] == 0xAA);
    CHECK(g[1] == 0x55);
    CHECK(Bytes(g.begin() + 2, g.end()) == good);
    auto w = decode(h.exchange(req));
    REQUIRE(w.ok());
    CHECK(w->id == 0x33);
    REQUIRE(h.link.write(req).ok());
    CHECK(h.link.read_some(transport::Millis(400))->empty());
    CHECK(*h.link.read_some(transport::Millis(400)) == good);
    CHECK(f.counters().total() == 4);
  }
  SECTION("reset in the middle of a block transfer: the drive forgets the transfer") {
    const Bytes info = encode(make_curve(kId, CurveOp::read_info, 1)).value();
    auto first = h.exchange(info);
    CHECK(first[6] == 0x04);
    CHECK(h.drive->transfer_active());
    f.schedule(2, sim::Fault::reset_drive());
    CHECK(h.exchange(info, 200).empty());  // rebooting: no answer
    CHECK_FALSE(h.drive->transfer_active());
    h.idle(3500);
    CHECK(h.exchange(info) == first);  // starts over at offset 0
    f.schedule(4, sim::Fault::reset_drive(true));
    CHECK(h.exchange(info) == first);  // instant reboot, answered
    CHECK(f.counters().drive_resets == 2);
  }
  SECTION("slow flash save takes the documented 10 s") {
    (void)h.exchange(encode(make_program(kId, ProgramOp::stop_mc)).value());
    f.schedule(2, sim::Fault::slow_flash());
    const auto t0 = h.link.clock().now_ns();
    CHECK(h.exchange(encode(make_ct(kId, CtOp::save_to_flash)).value(), 20000).size() == 14);
    CHECK(h.link.clock().now_ns() - t0 >= 10'000'000'000LL);
  }
  SECTION("close the link") {
    f.schedule(1, sim::Fault::close_link());
    auto w = h.link.write(req);
    REQUIRE_FALSE(w.ok());
    CHECK(w.error().code == make_error_code(Errc::link_closed));
    auto r = h.link.read_some(transport::Millis(10));
    REQUIRE_FALSE(r.ok());
    CHECK(r.error().code == make_error_code(Errc::link_closed));
  }
  SECTION("callback") {
    f.set_callback([](std::size_t ex, ByteView) {
      return ex % 2 == 1 ? std::vector<sim::Fault>{sim::Fault::drop_answer()}
                         : std::vector<sim::Fault>{};
    });
    int answered = 0;
    for (int i = 0; i < 10; ++i) answered += h.exchange(req, 50).empty() ? 0 : 1;
    CHECK(answered == 5);
    CHECK(f.counters().dropped_answers == 5);
  }
}

TEST_CASE("sim: discard_input drops answers already received", "[sim]") {
  SimHarness h("commissioned-axis.json");
  const Bytes req = encode(make_cfg(kId, CfgOp::read_rom, 0x13A2)).value();
  REQUIRE(h.link.write(req).ok());
  h.link.clock().advance_us(5000);
  h.link.discard_input();
  CHECK(h.link.pending_bytes() == 0);
  CHECK(h.link.read_some(transport::Millis(10))->empty());
}

}  // namespace sim_test_link
