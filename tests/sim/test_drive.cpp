// Semantics of the simulated drive (lib/sim/drive.cpp). The manual's own
// transcripts are in test_sim_manual.cpp; the line, its clock and faults in
// test_link.cpp; the state file in test_state_file.cpp.
#include <cstdio>
#include <filesystem>

#include "test_sim_harness.hpp"

// This file's own namespace: the test binary is a unity build (tests/CMakeLists.txt).
namespace sim_test_drive {

using namespace lmcfg;
using namespace lmcfg::codec;
using lmcfg::test::load_fixture;
using lmcfg::test::SimHarness;

namespace {
constexpr std::uint8_t kId = 0x11;

std::vector<std::uint16_t> modified_list(SimHarness& h, std::uint16_t base,
                                         std::uint8_t* last_state = nullptr) {
  std::vector<std::uint16_t> out;
  auto start = h.ask_iv(make_cfg(kId, CfgOp::start_modified, base), 0x58);
  REQUIRE(start.state == 0x00);
  for (int i = 0; i < 200; ++i) {
    auto r = h.ask_iv(make_cfg(kId, CfgOp::next_modified, base), 0x59);
    if (r.key != 0xFFFF) out.push_back(r.key);
    if (r.state == state::last_in_list) {
      if (last_state) *last_state = r.state;
      return out;
    }
    REQUIRE(r.state == 0x00);
  }
  FAIL("modified list did not end");
  return out;
}

DefaultResponse dr(const Telegram& t) {
  auto r = decode_default_response(t);
  REQUIRE(r.ok());
  return *r;
}
}  // namespace

// ---- parameters ------------------------------------------------------------------

TEST_CASE("sim: modified-UPID list follows ROM writes and ends with C6 on the last UPID", "[sim]") {
  SimHarness h("commissioned-axis.json");
  auto before = modified_list(h, 0x1000);
  CHECK(std::is_sorted(before.begin(), before.end()));
  CHECK(std::find(before.begin(), before.end(), 0x13A2) != before.end());
  CHECK(std::find(before.begin(), before.end(), 0x1710) == before.end());
  // 05 01: ROM write, answered with the new ROM value.
  auto w = h.ask_iv(make_cfg_write(kId, 0x1710, 77), 0x51);
  CHECK(w.state == 0x00);
  CHECK(w.value == 77u);
  auto after = modified_list(h, 0x1000);
  CHECK(after.size() == before.size() + 1);
  CHECK(std::find(after.begin(), after.end(), 0x1710) != after.end());
  // Writing the default back removes it; RAM is untouched by ROM writes.
  CHECK(h.ask_iv(make_cfg_write(kId, 0x1710, 0), 0x51).state == 0x00);
  CHECK(modified_list(h, 0x1000) == before);
  CHECK(h.drive->ram(0x1710) == 0u);
  // Every layer of the commissioned axis has modified parameters.
  for (int base : {0x0000, 0x1000, 0x2000, 0x3000})
    CHECK_FALSE(modified_list(h, static_cast<std::uint16_t>(base)).empty());
}

TEST_CASE("sim: empty modified list answers C6 with UPID FFFFh (configurable)", "[sim]") {
  SimHarness h("manual-drive.json");  // no OS parameter modified
  CHECK(h.ask_iv(make_cfg(kId, CfgOp::start_modified, 0x0000), 0x58).state == 0x00);
  auto r = h.ask_iv(make_cfg(kId, CfgOp::next_modified, 0x0000), 0x59);
  CHECK(r.state == 0xC6);
  CHECK(r.key == 0xFFFF);
  CHECK(r.value == 0u);
  h.drive->state().options.empty_list_upid = 0x0000;
  CHECK(h.ask_iv(make_cfg(kId, CfgOp::start_modified, 0x3000), 0x58).state == 0x00);
  CHECK(h.ask_iv(make_cfg(kId, CfgOp::next_modified, 0x3000), 0x59).key == 0x0000);
}

TEST_CASE("sim: UPID list ends with C6 repeating the last UPID", "[sim]") {
  SimHarness h("commissioned-axis.json");
  h.ask_iv(make_cfg(kId, CfgOp::start_upid_list, 0x3000), 0x5A);
  std::vector<std::uint16_t> seen;
  for (;;) {
    auto a = h.ask(make_cfg(kId, CfgOp::next_upid, 0));
    auto e = decode_upid_list_entry(a);
    REQUIRE(e.ok());
    if (e->state == 0xC6) {
      CHECK(e->upid == seen.back());
      break;
    }
    seen.push_back(e->upid);
    CHECK(e->address_usage == 0x000F);
  }
  CHECK(seen == std::vector<std::uint16_t>{0x3010, 0x3020, 0x3030});
}

TEST_CASE("sim: layer defaulting (03 12h) sets MC ROM to default, RAM follows only after reset",
          "[sim]") {
  SimHarness h("commissioned-axis.json");
  REQUIRE(h.drive->rom(0x13A2) == 40u);
  const auto t0 = h.link.clock().now_ns();
  auto a = h.ask(make_param_default_layer(kId, 2));
  CHECK(dr(a).comm_state == 0x00);
  CHECK(h.link.clock().now_ns() - t0 >= 1'200'000'000LL);
  CHECK(h.drive->rom(0x13A2) == 15u);
  CHECK(h.drive->rom(0x200E) == 2u);  // other layers untouched
  CHECK(h.drive->ram(0x13A2) == 40u);
  CHECK(h.ask(make_program(kId, ProgramOp::reset_after_completion)).sub == 0x60);
  CHECK(h.drive->ram(0x13A2) == 15u);
}

TEST_CASE("sim: RAM reloads from ROM at reset and at MC start", "[sim]") {
  SimHarness h("commissioned-axis.json");
  CHECK(dr(h.ask(make_param_write(kId, ParamOp::write_ram, 0x13A2, 99))).comm_state == 0x00);
  CHECK(dr(h.ask(make_param_read(kId, ParamOp::read_ram, 0x13A2))).value == 99u);
  CHECK(dr(h.ask(make_program(kId, ProgramOp::reset_immediate))).comm_state == 0x00);
  h.idle(3500);
  CHECK(dr(h.ask(make_param_read(kId, ParamOp::read_ram, 0x13A2))).value == 40u);
  CHECK(dr(h.ask(make_param_write(kId, ParamOp::write_ram, 0x13A2, 98))).comm_state == 0x00);
  CHECK(h.ask(make_program(kId, ProgramOp::start_after_completion)).sub == 0x60);
  CHECK(h.drive->ram(0x13A2) == 40u);
}

TEST_CASE("sim: out-of-range and read-only ROM writes are refused with C9 (policy configurable)",
          "[sim]") {
  SimHarness h("commissioned-axis.json");
  auto r = h.ask_iv(make_cfg_write(kId, 0x1290, 7), 0x51);  // max 1
  CHECK(r.state == 0xC9);
  CHECK(r.value == 0u);                                                 // the unchanged ROM value
  CHECK(h.ask_iv(make_cfg_write(kId, 0x2136, 1), 0x51).state == 0xC9);  // AU 1001h: no ROM write
  CHECK(dr(h.ask(make_param_write(kId, ParamOp::write_rom, 0x1290, 7))).comm_state == 0xC9);
  CHECK(h.ask_iv(make_cfg_write(kId, 0x1040, 0xFFFFFF00), 0x51).state ==
        0x00);  // SINT16 -256 within range
  h.drive->state().options.write_policy = sim::WritePolicy::clamp;
  CHECK(h.ask_iv(make_cfg_write(kId, 0x1290, 7), 0x51).value == 1u);
}

TEST_CASE("sim: C8 unknown UPID, C3 undefined main ID, C4 undefined sub ID", "[sim]") {
  SimHarness h("commissioned-axis.json");
  CHECK(dr(h.ask(make_param_read(kId, ParamOp::read_ram, 0x1234))).comm_state == 0xC8);
  auto c = h.ask_iv(make_cfg(kId, CfgOp::read_rom, 0x1234), 0x50);
  CHECK(c.state == 0xC8);
  CHECK(c.key == 0x1234);
  CHECK(dr(h.ask(Telegram{kId, 0x00, 0x09, {}})).comm_state == 0xC3);
  CHECK(dr(h.ask(Telegram{kId, 0x02, 0x05, {0xA2, 0x13}})).comm_state == 0xC4);
  CHECK(dr(h.ask(Telegram{kId, 0x09, 0x06, {}})).comm_state == 0xC4);
  CHECK(h.drive->stats().error_answers == 5);
}

// ---- curves and command table -------------------------------------------------------

TEST_CASE("sim: curve sizes of a missing curve are 0/0 (or C8 by option)", "[sim]") {
  SimHarness h("commissioned-axis.json");
  auto r = h.ask_iv(make_curve(kId, CurveOp::read_sizes, 50), 0x40);
  CHECK(r.state == 0x00);
  CHECK(r.value == 0u);
  CHECK(h.ask_iv(make_curve(kId, CurveOp::read_sizes, 2), 0x40).value == (70u | (20u << 16)));
  h.drive->state().options.missing_curve_zero_sizes = false;
  CHECK(h.ask_iv(make_curve(kId, CurveOp::read_sizes, 50), 0x40).state == 0xC8);
  CHECK(h.ask_iv(make_curve(kId, CurveOp::read_info, 50), 0x40).state == 0xC8);
}

TEST_CASE("sim: flash saves are refused while MC runs and take their time when stopped", "[sim]") {
  SimHarness h("commissioned-axis.json");
  h.drive->state().curves_ram.erase(2);
  h.drive->state().ct_ram.erase(1);
  CHECK(h.ask_iv(make_curve(kId, CurveOp::save_to_flash), 0x40).state == 0xC4);
  CHECK(h.ask_iv(make_ct(kId, CtOp::save_to_flash), 0x80).state == 0xC4);
  CHECK(h.drive->state().curves_flash.count(2) == 1);
  CHECK(dr(h.ask(make_program(kId, ProgramOp::stop_mc))).status_word == 0);
  auto t0 = h.link.clock().now_ns();
  CHECK(h.ask_iv(make_curve(kId, CurveOp::save_to_flash), 0x40).state == 0x00);
  CHECK(h.link.clock().now_ns() - t0 >= 2'000'000'000LL);
  CHECK(h.drive->state().curves_flash.count(2) == 0);
  CHECK(h.ask_iv(make_ct(kId, CtOp::save_to_flash), 0x80).state == 0x00);
  CHECK(h.drive->state().ct_flash.count(1) == 0);
  CHECK(h.drive->stats().flash_saves == 2);
}

TEST_CASE("sim: command table setup/write/read round trip and defined list", "[sim]") {
  SimHarness h("used-spare.json");
  Bytes entry(64);
  for (std::size_t i = 0; i < entry.size(); ++i) entry[i] = static_cast<std::uint8_t>(i * 3);
  CHECK(h.ask_iv(make_ct_setup_write(kId, 40, 64), 0x83).state == 0x00);
  for (std::size_t o = 0; o < 64; o += 4) {
    auto r = h.ask_iv(make_ct_write(kId, 40, {entry[o], entry[o + 1], entry[o + 2], entry[o + 3]}),
                      0x84);
    CHECK(r.state == (o + 4 < 64 ? 0x04 : 0x00));
  }
  CHECK(h.drive->state().ct_ram.at(40) == entry);
  CHECK(h.ask_iv(make_ct(kId, CtOp::setup_read, 40), 0x85).value == 64u);
  CHECK(h.ask_iv(make_ct(kId, CtOp::setup_read, 41), 0x85).value == 0u);
  Bytes back;
  for (int i = 0; i < 16; ++i) {
    auto r = h.ask_iv(make_ct(kId, CtOp::read_data, 40), 0x86);
    auto raw = r.raw();
    back.insert(back.end(), raw.begin(), raw.end());
  }
  CHECK(back == entry);
  // 3, 9 (fixture) and 40: block 0 has bits 3 and 9 cleared, block 1 bit 8.
  CHECK(h.ask_iv(make_ct_defined_list(kId, 0), 0x87).value ==
        (0xFFFFFFFFu & ~(1u << 3) & ~(1u << 9)));
  CHECK(h.ask_iv(make_ct_defined_list(kId, 1, false), 0x87).value == (0xFFFFFFFFu & ~(1u << 8)));
}

// ---- checksums ---------------------------------------------------------------------

TEST_CASE("sim: checksum modes add and CRC, C1 answer on a bad checksum", "[sim]") {
  for (auto mode : {ChecksumMode::add, ChecksumMode::crc_ccitt}) {
    auto s = load_fixture("manual-drive.json");
    s.checksum.mode = mode;
    SimHarness h(s);
    INFO("mode " << static_cast<int>(mode));
    auto ok = h.ask_iv(make_cfg(kId, CfgOp::read_rom, 0x13A2), 0x50);
    CHECK(ok.value == 0x0Au);
    Bytes bad = encode(make_cfg(kId, CfgOp::read_rom, 0x13A2), s.checksum).value();
    bad[bad.size() - 2] ^= 0x5A;
    auto rx = h.exchange(bad);
    auto t = decode(rx, s.checksum);
    REQUIRE(t.ok());
    CHECK(dr(*t).comm_state == 0xC1);
    // Not addressed to us: no answer even though the checksum is wrong.
    Bytes other = encode(make_cfg(0x22, CfgOp::read_rom, 0x13A2), s.checksum).value();
    other[other.size() - 2] ^= 0x5A;
    CHECK(h.exchange(other, 50).empty());
    h.drive->state().options.respond_on_checksum_error = false;
    CHECK(h.exchange(bad, 50).empty());
  }
}

TEST_CASE("sim: C2 answer when the end of telegram is missing", "[sim]") {
  SimHarness h("manual-drive.json");
  Bytes broken = from_hex("01 11 05 02 00 05 A2 13 05").value();
  auto rx = h.exchange(broken);
  REQUIRE_FALSE(rx.empty());
  CHECK(dr(decode(rx).value()).comm_state == 0xC2);
}

// ---- options -------------------------------------------------------------------------

TEST_CASE(
    "sim: refuse_config_while_mc_runs refuses ROM writes and defaulting while MC runs, not after "
    "the stop (LinRS §10)",
    "[sim][mc-stopped]") {
  // LinRS §10: "For configuring it is needed to stop the MC-SW of the servo
  // controller first"; the §9.2 capture writes ROM with MC running: an option.
  auto s = load_fixture("commissioned-axis.json");
  {
    SimHarness accepting(s);  // the default plays the §9.2 capture
    CHECK(dr(accepting.ask(make_param_write(kId, ParamOp::write_rom, 0x13A2, 12))).comm_state ==
          0x00);
  }
  s.options.refuse_config_while_mc_runs = true;
  SimHarness h(s);
  CHECK(dr(h.ask(make_param_write(kId, ParamOp::write_rom, 0x13A2, 12))).comm_state == 0xC4);
  CHECK(dr(h.ask(make_param_write(kId, ParamOp::write_ram_rom, 0x13A2, 12))).comm_state == 0xC4);
  CHECK(h.ask_iv(make_cfg_write(kId, 0x13A2, 12), 0x51).state == 0xC4);
  CHECK(dr(h.ask(make_param_default_layer(kId, 2))).comm_state == 0xC4);
  CHECK(h.ask_iv(make_cfg_default_layer(kId, 2), 0x5D).state == 0xC4);
  CHECK(h.drive->rom(0x13A2) == 40u);  // nothing changed
  // RAM is not configuration: written while MC runs.
  CHECK(dr(h.ask(make_param_write(kId, ParamOp::write_ram, 0x13A2, 11))).comm_state == 0x00);
  CHECK(h.drive->ram(0x13A2) == 11u);
  CHECK(dr(h.ask(make_program(kId, ProgramOp::stop_mc))).status_word == 0);
  CHECK(h.ask_iv(make_cfg_write(kId, 0x13A2, 12), 0x51).state == 0x00);
  CHECK(h.drive->rom(0x13A2) == 12u);
  // The option survives the state file.
  const auto j = sim::to_json(h.drive->state());
  CHECK(j["options"]["refuse_config_while_mc_runs"] == true);
  CHECK(j["options"]["config_refused_state"] == "C4");
  auto back = sim::from_json(j);
  REQUIRE(back.ok());
  CHECK(back->options.refuse_config_while_mc_runs);
}

}  // namespace sim_test_drive
