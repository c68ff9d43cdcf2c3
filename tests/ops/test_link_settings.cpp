// ops::link_settings (`lmcfg link`) against the in-process simulated drive.
// LinRS §10.2 gives 200Eh = 2 "By Parameter", 2012h = 8 "38400 Baud",
// 206Ch = 3 "By Parameter" and 2076h (the MACID); §15 names the checksum
// without a UPID, so the drive here keeps it at 20A0h, a stand-in the test
// gives both the simulator (options.checksum_param) and the tool (--map).
#include <catch2/catch.hpp>
#include <filesystem>

#include "e2e_support.hpp"
#include "files.hpp"
#include "link/session.hpp"
#include "ops/link_settings.hpp"
#include "ops/recovery.hpp"
#include "sim/state_file.hpp"

// This file's own namespace: the test binary is a unity build (tests/CMakeLists.txt).
namespace ops_test_link_settings {

using namespace lmcfg;
namespace fs = std::filesystem;

namespace {

constexpr std::uint16_t kChecksumUpid = 0x20A0;  // stand-in: no seed gives it

// used-spare.json (57600 Bd and MACID 11h from its hex switches) with a
// checksum parameter the simulated firmware applies at reset.
void write_spare(const fs::path& file, bool silent_after_reset = false) {
  auto st = sim::load_state(test::sim_fixture("used-spare.json"));
  REQUIRE(st.ok());
  sim::Parameter p;
  p.upid = kChecksumUpid;
  p.name = "Checksum (test stand-in)";
  p.max = 2;
  st->put(p);
  st->options.checksum_param =
      sim::Options::CommParam{kChecksumUpid, {{0, "none"}, {1, "add"}, {2, "crc-ffff"}}};
  st->options.silent_after_reset = silent_after_reset;
  REQUIRE(sim::save_state(*st, file.string()).ok());
}

const std::vector<std::string> kMap = {"checksum@20A0:none=0,add=1,crc=2"};

struct Rig {
  test::ScratchDir dir{"link-settings"};
  fs::path state = dir.path / "spare.sim.json";
  fs::path record = dir.path / "link-record.json";
  std::unique_ptr<link::Session> session;
  explicit Rig(bool silent = false) {
    write_spare(state, silent);
    link::LinkSpec lo;
    lo.port = *link::parse_port("sim:" + state.string());
    lo.client.timeout = transport::Millis(50);
    auto s = link::open_session(lo);
    REQUIRE(s.ok());
    session = std::move(s).value();
  }
};

}  // namespace

TEST_CASE("link: the settings as the drive holds them, with their sources (seed 003 §10.2, §15)",
          "[link]") {
  Rig rig;
  auto map = ops::link_map(db::Database::empty(), kMap);
  REQUIRE(map.ok());
  auto st = ops::read_link_settings(*rig.session, *map);
  REQUIRE(st.ok());
  using S = ops::LinkSetting;
  CHECK((*st)[S::baud_source].rom == 1u);
  CHECK((*st)[S::baud_source].text == "hex switch S1");
  CHECK((*st)[S::baud].rom == 32u);
  CHECK((*st)[S::baud].text.empty());  // seed 003 states only 8 = 38400
  CHECK((*st)[S::baud].note == "raw value 32 not in the map");
  CHECK((*st)[S::macid_source].text == "hex switches (S2, or S1 and S2)");
  CHECK((*st)[S::macid].text == "11h");
  CHECK((*st)[S::checksum].text == "none");
  CHECK((*st)[S::checksum].note == "--map");
  CHECK_FALSE((*st)[S::parity].rom);
  CHECK((*st)[S::parity].note ==
        "UPID unknown: seed 003 §15 names the setting but not its UPID; give it with --map "
        "parity@UPID:VALUE=RAW,...");
  CHECK(link::link_options_of(st->in_use) == "--baud 57600 --id 0x11 --checksum none");
  // 2012h's default on the drive is 16: "57600 Bit/s (default)" (LinRS §15).
  REQUIRE(ops::learn_from_drive(*rig.session, *map).ok());
  CHECK((*map)[S::baud].raw_of("57600") == 16u);
}

TEST_CASE("link: --map entries are checked", "[link]") {
  auto bad = ops::link_map(db::Database::empty(), {"baud@2013:115200=32"});
  REQUIRE_FALSE(bad.ok());
  CHECK(bad.error().message ==
        "--map 'baud@2013:115200=32': seed 003 §10.2 gives baud rate the UPID 2012h; expected "
        "SETTING[@UPID]:VALUE=RAW[,VALUE=RAW...], e.g. checksum@20A0:none=0,add=1,crc=2 or "
        "baud:115200=32");
  auto odd = ops::link_map(db::Database::empty(), {"parity@20B0:strange=1"});
  REQUIRE_FALSE(odd.ok());
  CHECK(odd.error().message.rfind(
            "--map 'parity@20B0:strange=1': parity 'strange' is not one of none, even, odd;", 0) ==
        0);
  auto ok = ops::link_map(db::Database::empty(), {"baud:115200=32,57600=0x10"});
  REQUIRE(ok.ok());
  CHECK((*ok)[ops::LinkSetting::baud].raw_of("115200") == 32u);
  CHECK((*ok)[ops::LinkSetting::baud].raw_of("57600") == 16u);
  CHECK((*ok)[ops::LinkSetting::baud].raw_of("38400") == 8u);  // LinRS §10.2
}

TEST_CASE("link: what the map cannot express is refused before anything is written", "[link]") {
  Rig rig;
  auto map = ops::link_map(db::Database::empty(), {});
  REQUIRE(map.ok());
  auto st = ops::read_link_settings(*rig.session, *map);
  REQUIRE(st.ok());
  ops::LinkChange fast;
  fast.baud = 115200;
  auto p = ops::plan_link_change(*rig.session, *map, *st, fast);
  REQUIRE_FALSE(p.ok());
  CHECK(p.error().code == make_error_code(Errc::invalid_argument));
  CHECK(p.error().message ==
        "--set-baud 115200: no raw value of 2012h baud rate is known for 115200 (known: 38400 = "
        "8; seed 003 states only 8 = 38400 Baud, §10.2); give it with --map baud:115200=RAW; "
        "nothing written");
  ops::LinkChange crc;
  crc.checksum = link::parse_checksum("crc").value();
  p = ops::plan_link_change(*rig.session, *map, *st, crc);
  REQUIRE_FALSE(p.ok());
  CHECK(p.error().message ==
        "--set-checksum crc-ffff: LinRS 3V27 §4.4 gives the checksum's UPID, 2080h, but no source "
        "its raw values; give them with --map checksum:VALUE=RAW,...; nothing written");
  REQUIRE(rig.session->close().ok());
  auto after = sim::load_state(rig.state.string());
  REQUIRE(after.ok());
  CHECK(after->params.at(0x2012).rom == 32);
  CHECK(after->params.at(0x200E).rom == 1);
}

TEST_CASE(
    "link: crc and 38400 Bd: ROM written value before source, reset, found, read back, record "
    "deleted (seed 003 §10, §10.2, §13.1)",
    "[link]") {
  Rig rig;
  auto map = ops::link_map(db::Database::empty(), kMap);
  REQUIRE(map.ok());
  auto st = ops::read_link_settings(*rig.session, *map);
  REQUIRE(st.ok());
  ops::LinkChange ch;
  ch.baud = 38400;
  ch.checksum = link::parse_checksum("crc").value();
  auto plan = ops::plan_link_change(*rig.session, *map, *st, ch);
  REQUIRE(plan.ok());
  REQUIRE(plan->writes.size() == 3);
  CHECK(plan->writes[0].text == "2012h baud rate: 32 -> 8 (38400)");
  CHECK(plan->writes[1].text == "200Eh baud rate source: 1 (hex switch S1) -> 2 (By Parameter)");
  CHECK(plan->writes[2].text == "20A0h checksum: 0 (none) -> 2 (crc-ffff)");
  CHECK(link::link_options_of(plan->after) == "--baud 38400 --id 0x11 --checksum crc-ffff");

  auto rep = ops::apply_link_change(*rig.session, *map, *plan, "sim:spare", rig.record);
  REQUIRE(rep.ok());
  CHECK_FALSE(rep->scanned);
  CHECK(rep->relink.summary == "the drive answers at 38400 Bd, MACID 11h, checksum crc-ffff");
  CHECK(rep->after[ops::LinkSetting::checksum].rom == 2u);
  CHECK(rep->after[ops::LinkSetting::baud].text == "38400");
  CHECK_FALSE(fs::exists(rig.record));
  CHECK(rig.session->line().baud == 38400);
  REQUIRE(rig.session->close().ok());
  auto after = sim::load_state(rig.state.string());
  REQUIRE(after.ok());
  CHECK(after->link.baud == 38400);
  CHECK(after->checksum.mode == codec::ChecksumMode::crc_ccitt);
  CHECK(after->checksum.crc_init == 0xFFFF);
}

TEST_CASE("link: a drive lost after the reset keeps its recovery record and says how to find it",
          "[link]") {
  Rig rig(true);
  auto map = ops::link_map(db::Database::empty(), kMap);
  REQUIRE(map.ok());
  auto st = ops::read_link_settings(*rig.session, *map);
  REQUIRE(st.ok());
  ops::LinkChange ch;
  ch.checksum = link::parse_checksum("add").value();
  auto plan = ops::plan_link_change(*rig.session, *map, *st, ch);
  REQUIRE(plan.ok());
  auto rep = ops::apply_link_change(*rig.session, *map, *plan, "sim:spare", rig.record);
  REQUIRE_FALSE(rep.ok());
  CHECK(rep.error().code == make_error_code(Errc::timeout));
  const std::string& m = rep.error().message;
  INFO(m);
  CHECK(m.rfind("written and reset, but the drive was not found again: after the reset the drive "
                "answered none of the ",
                0) == 0);
  CHECK(m.find("a scan of MACID 11h at every rate, checksum and parity found nothing. The drive "
               "holds 20A0h = 1 in ROM and restarted with them (expected: --baud 57600 --id 0x11 "
               "--checksum add); the recovery record " +
               rig.record.string() +
               " holds the previous values (--baud 57600 --id 0x11 --checksum none). Find it "
               "with: lmcfg scan --port sim:spare") != std::string::npos);
  auto kept = ops::load_recovery(rig.record);
  REQUIRE(kept.ok());
  REQUIRE(*kept);
  CHECK((*kept)->command == "link");
  CHECK((*kept)->expect == "--baud 57600 --id 0x11 --checksum add");
  REQUIRE((*kept)->keep.size() == 1);
  CHECK((*kept)->keep[0].upid == kChecksumUpid);
  CHECK((*kept)->keep[0].value == 0);
}

TEST_CASE("link: a MACID another drive on the line answers to is refused (seed 003 §3.3)",
          "[link]") {
  test::ScratchDir dir("link-macid");
  write_spare(dir.path / "a.json");
  auto b = sim::load_state(test::sim_fixture("used-spare.json"));
  REQUIRE(b.ok());
  b->macid = 0x12;
  b->switches = sim::HexSwitches{0x12, 57600};
  REQUIRE(sim::save_state(*b, (dir.path / "b.json").string()).ok());
  link::LinkSpec lo;
  lo.port = *link::parse_port("sim:" + (dir.path / "a.json").string() + "," +
                              (dir.path / "b.json").string());
  lo.client.timeout = transport::Millis(50);
  auto s = link::open_session(lo);
  REQUIRE(s.ok());
  auto map = ops::link_map(db::Database::empty(), {});
  REQUIRE(map.ok());
  auto st = ops::read_link_settings(**s, *map);
  REQUIRE(st.ok());
  ops::LinkChange ch;
  ch.macid = 0x12;
  auto p = ops::plan_link_change(**s, *map, *st, ch);
  REQUIRE_FALSE(p.ok());
  CHECK(p.error().message ==
        "--set-id 12h: a drive already answers as MACID 12h on this line; nothing written");
  ch.macid = 0x13;
  p = ops::plan_link_change(**s, *map, *st, ch);
  REQUIRE(p.ok());
  REQUIRE(p->writes.size() == 2);
  CHECK(p->writes[0].text == "2076h MACID: 17 (11h) -> 19 (13h)");
  CHECK(p->writes[1].text ==
        "206Ch MACID source: 1 (hex switches (S2, or S1 and S2)) -> 3 (By Parameter)");
  CHECK((*s)->client().options().id == 0x11);
}

TEST_CASE(
    "link: parity and stop bits through --map, the drive is found at even parity, 2 stop bits",
    "[link]") {
  test::ScratchDir dir("link-parity");
  auto st = sim::load_state(test::sim_fixture("used-spare.json"));
  REQUIRE(st.ok());
  for (std::uint16_t upid : {std::uint16_t{0x20B0}, std::uint16_t{0x20B2}}) {
    sim::Parameter p;
    p.upid = upid;
    p.max = 2;
    st->put(p);
  }
  // Stand-ins: LinRS §15 names Parity (None, Even, Odd) and Stop Bit (1, 2)
  // without UPIDs or raw values.
  st->options.parity_param =
      sim::Options::CommParam{0x20B0, {{0, "none"}, {1, "even"}, {2, "odd"}}};
  st->options.stop_bits_param = sim::Options::CommParam{0x20B2, {{0, "1"}, {1, "2"}}};
  const fs::path file = dir.path / "spare.json";
  REQUIRE(sim::save_state(*st, file.string()).ok());
  link::LinkSpec lo;
  lo.port = *link::parse_port("sim:" + file.string());
  lo.client.timeout = transport::Millis(50);
  auto s = link::open_session(lo);
  REQUIRE(s.ok());
  auto map = ops::link_map(db::Database::empty(),
                           {"parity@20B0:none=0,even=1,odd=2", "stop-bits@20B2:1=0,2=1"});
  REQUIRE(map.ok());
  auto now = ops::read_link_settings(**s, *map);
  REQUIRE(now.ok());
  ops::LinkChange ch;
  ch.parity = transport::Parity::even;
  ch.stop_bits = 2;
  auto plan = ops::plan_link_change(**s, *map, *now, ch);
  REQUIRE(plan.ok());
  REQUIRE(plan->writes.size() == 2);
  CHECK(plan->writes[0].text == "20B0h parity: 0 (none) -> 1 (even)");
  CHECK(plan->writes[1].text == "20B2h stop bits: 0 (1) -> 1 (2)");
  auto rep = ops::apply_link_change(**s, *map, *plan, "sim:spare", dir.path / "record.json");
  REQUIRE(rep.ok());
  CHECK(rep->relink.summary ==
        "the drive answers at 57600 Bd, MACID 11h, checksum none, parity even, 2 stop bits");
  CHECK(link::link_options_of(rep->relink.used) ==
        "--baud 57600 --parity even --stop-bits 2 --id 0x11 --checksum none");
  REQUIRE((*s)->close().ok());
  auto after = sim::load_state(file.string());
  REQUIRE(after.ok());
  CHECK(after->link.parity == transport::Parity::even);
  CHECK(after->link.stop_bits == 2);
}

TEST_CASE("LinRS 3V27 §4.4 link: 2080h is the checksum's UPID, its raw values come from --map",
          "[link][families]") {
  using S = ops::LinkSetting;
  auto plain = ops::link_map(db::Database::empty(), {});
  REQUIRE(plain.ok());
  CHECK((*plain)[S::checksum].upid == std::optional<std::uint16_t>(0x2080));
  CHECK((*plain)[S::checksum].codes.empty());
  CHECK((*plain)[S::checksum].source == "LinRS 3V27 §4.4");
  // Raw values without a UPID: 2080h's.
  auto raw = ops::link_map(db::Database::empty(), {"checksum:none=0,crc=2"});
  REQUIRE(raw.ok());
  CHECK((*raw)[S::checksum].upid == std::optional<std::uint16_t>(0x2080));
  CHECK((*raw)[S::checksum].raw_of("crc-ffff") == 2u);
  // A firmware whose documentation names another UPID: --map replaces 2080h
  // (the seed's own §10.2 UPIDs cannot be replaced).
  auto other = ops::link_map(db::Database::empty(), kMap);
  REQUIRE(other.ok());
  CHECK((*other)[S::checksum].upid == std::optional<std::uint16_t>(kChecksumUpid));
  CHECK((*other)[S::checksum].source == "--map");
  auto baud = ops::link_map(db::Database::empty(), {"baud@2013:38400=8"});
  REQUIRE_FALSE(baud.ok());
}

}  // namespace ops_test_link_settings
