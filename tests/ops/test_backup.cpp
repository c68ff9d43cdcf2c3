// Backup (lib/ops/backup.cpp) against the in-process simulated drive: what a
// capture holds (modified lists, full captures, curves, command table, scope
// and identity), the types and defaults it records, the report on how far a
// value read can be trusted, read telegrams only, and the display helpers the
// other operations share (display_value, annotate, the command table decoder).
#include <algorithm>
#include <catch2/catch.hpp>
#include <regex>
#include <set>

#include "common/version.hpp"
#include "config/config_io.hpp"
#include "db/database.hpp"
#include "db_test_support.hpp"
#include "ops/backup.hpp"
#include "test_reliability_support.hpp"

// This file's own namespace: the test binary is a unity build (tests/CMakeLists.txt).
namespace ops_test_backup {

using namespace lmcfg;

namespace {

using test::modified_rom;

// The requests of one message group (main ID) among what was sent.
std::size_t requests_of(const test::WireRecorder& w, std::uint8_t main) {
  std::size_t n = 0;
  codec::StreamDecoder dec;
  for (const auto& chunk : w.tx) {
    dec.feed(chunk);
    while (auto t = dec.next())
      if (t->ok() && t->value().main == main) ++n;
  }
  return n;
}

// A whole backup's report.
ops::BackupReport report_of(client::Client& c) {
  ops::BackupReport report;
  ops::BackupOptions bo;
  bo.report = &report;
  REQUIRE(ops::backup(c, bo, db::Database::empty()).ok());
  return report;
}

}  // namespace

TEST_CASE("e2e: a backup records each parameter's type and default, asked from the drive",
          "[e2e][backup]") {
  test::SimRig source("commissioned-axis.json");
  auto captured = ops::backup(*source.client, ops::BackupOptions{}, db::Database::empty());
  REQUIRE(captured.ok());
  const auto& file = *captured;
  std::size_t n = 0;
  for (int layer = 1; layer <= 4; ++layer) {
    for (const auto& p : file.layer(layer)) {
      const auto& truth = source.drive->state().params.at(p.upid);
      INFO("UPID " << p.upid);
      CHECK(p.type == std::optional<std::uint8_t>(static_cast<std::uint8_t>(truth.type)));
      CHECK(p.default_value == std::optional<std::uint32_t>(truth.def));
      ++n;
    }
  }
  CHECK(n == modified_rom(*source.drive).size());
  // The records survive the file formats.
  for (auto fmt : {config::FileFormat::json, config::FileFormat::xml}) {
    auto text = config::write_config_text(file, fmt);
    REQUIRE(text.ok());
    auto back = config::read_config_text(*text, "mem", fmt);
    REQUIRE(back.ok());
    CHECK(back->layers == file.layers);
  }
  // --no-describe: nothing is asked; only what a database knows is recorded.
  test::SimRig again("commissioned-axis.json");
  ops::BackupOptions bo;
  bo.ask_drive = false;
  auto bare = ops::backup(*again.client, bo, db::Database::empty());
  REQUIRE(bare.ok());
  for (const auto& l : bare->layers)
    for (const auto& p : l) CHECK_FALSE((p.type || p.default_value));
}

TEST_CASE("backup: a capture holds the modified lists, curves and command table, read only",
          "[backup]") {
  test::SimRig rig("commissioned-axis.json");
  std::set<std::string> phases;
  ops::BackupOptions bo;
  bo.progress = [&](const std::string& phase, std::size_t, std::size_t) { phases.insert(phase); };
  auto cfg = ops::backup(*rig.client, bo, db::Database::empty());
  REQUIRE(cfg.ok());
  CHECK(test::backup_vs_drive(*cfg, *rig.drive).empty());
  CHECK(rig.wire->write_telegrams() == 0);
  CHECK(cfg->scope.layers == std::array<bool, 4>{true, true, true, true});
  CHECK(cfg->scope.parameters == config::ParamSet::modified);
  CHECK(cfg->scope.curves);
  CHECK(cfg->scope.command_table);
  CHECK(cfg->identity.macid == "0x11");
  CHECK(cfg->identity.tool_version == kToolVersion);
  CHECK(cfg->identity.upid_fingerprint.empty());  // only a full capture has one
  CHECK(std::regex_match(cfg->identity.captured_at,
                         std::regex("[0-9]{4}-[0-9]{2}-[0-9]{2}T[0-9]{2}:[0-9]{2}:[0-9]{2}Z")));
  CHECK(phases.count("parameters MC"));
  CHECK(phases.count("types and defaults MC"));
  CHECK(phases.count("curves"));
  CHECK(phases.count("command table"));
  // Canonical: parameters in UPID order in each layer.
  for (const auto& l : cfg->layers)
    CHECK(std::is_sorted(l.begin(), l.end(),
                         [](const auto& a, const auto& b) { return a.upid < b.upid; }));
}

TEST_CASE("backup: layers, curves and the command table left out are neither read nor in scope",
          "[backup]") {
  test::SimRig rig("commissioned-axis.json");
  ops::BackupOptions bo;
  bo.layers = {false, true, false, false};
  bo.curves = false;
  bo.command_table = false;
  auto cfg = ops::backup(*rig.client, bo, db::Database::empty());
  REQUIRE(cfg.ok());
  CHECK(cfg->scope.layers == std::array<bool, 4>{false, true, false, false});
  CHECK_FALSE(cfg->scope.curves);
  CHECK_FALSE(cfg->scope.command_table);
  CHECK(cfg->curves.empty());
  CHECK(cfg->ct_entries.empty());
  CHECK(cfg->layer(1).empty());
  CHECK(cfg->layer(3).empty());
  CHECK(cfg->layer(4).empty());
  std::set<std::uint16_t> mc;
  for (const auto& [upid, v] : modified_rom(*rig.drive))
    if (upid >= 0x1000 && upid <= 0x1EFF) mc.insert(upid);  // LinRS §10.2: layer 2 range
  std::set<std::uint16_t> got;
  for (const auto& p : cfg->layer(2)) got.insert(p.upid);
  CHECK(got == mc);
  CHECK(requests_of(*rig.wire, 0x04) == 0);  // §11 curve group: not a telegram
  CHECK(requests_of(*rig.wire, 0x08) == 0);  // §12 command table group: not a telegram
}

TEST_CASE(
    "LinRS §10.3 backup: a full capture holds every ROM-writable UPID with its type and a "
    "fingerprint of the UPID set",
    "[backup]") {
  test::SimRig rig("commissioned-axis.json");
  ops::BackupOptions bo;
  bo.full = true;
  bo.curves = bo.command_table = false;
  auto cfg = ops::backup(*rig.client, bo, db::Database::empty());
  REQUIRE(cfg.ok());
  CHECK(cfg->scope.parameters == config::ParamSet::full);
  std::map<std::uint16_t, std::uint32_t> want, got;
  for (const auto& [upid, p] : rig.drive->state().params)
    if (p.has_rom()) want[upid] = p.rom;
  for (const auto& l : cfg->layers)
    for (const auto& p : l) {
      got[p.upid] = p.value;
      const auto& truth = rig.drive->state().params.at(p.upid);
      INFO("UPID " << p.upid);
      CHECK(p.type == std::optional<std::uint8_t>(static_cast<std::uint8_t>(truth.type)));
      CHECK(p.default_value == std::optional<std::uint32_t>(truth.def));
    }
  CHECK(got == want);
  CHECK(std::regex_match(cfg->identity.upid_fingerprint, std::regex("fnv1a64:[0-9a-f]{16}")));
  // The same drive, the same fingerprint; another UPID set, another one.
  test::SimRig same("commissioned-axis.json");
  auto again = ops::backup(*same.client, bo, db::Database::empty());
  REQUIRE(again.ok());
  CHECK(again->identity.upid_fingerprint == cfg->identity.upid_fingerprint);
  auto other_state = rig.drive->state();
  other_state.params.erase(other_state.params.begin());
  auto other_drive = std::make_shared<sim::Drive>(other_state);
  test::FaultRig other(other_drive);
  auto third = ops::backup(*other.client, bo, db::Database::empty());
  REQUIRE(third.ok());
  CHECK(third->identity.upid_fingerprint != cfg->identity.upid_fingerprint);
}

TEST_CASE(
    "backup: curves up to the highest ID probed, a listed entry that is not there left out "
    "with a note",
    "[backup]") {
  auto state = test::load_sim_drive("commissioned-axis.json")->state();
  REQUIRE(state.curves_ram.size() >= 2);
  const std::uint16_t first = state.curves_ram.begin()->first;
  state.ct_ram[200] = Bytes{};  // listed as defined (§12), size 0 on its query
  auto drive = std::make_shared<sim::Drive>(state);
  test::FaultRig rig(drive);
  auto curves = ops::read_curves(*rig.client, first, nullptr, "curves");
  REQUIRE(curves.ok());
  REQUIRE(curves->size() == 1);
  CHECK((*curves)[0].id == first);
  CHECK((*curves)[0].info == state.curves_ram.at(first).info);
  CHECK((*curves)[0].data == state.curves_ram.at(first).data);
  auto none = ops::read_curves(*rig.client, 0, nullptr, "curves");
  REQUIRE(none.ok());
  CHECK(none->empty());

  std::vector<std::string> notes;
  auto ct = ops::read_command_table(*rig.client, nullptr, "command table", notes);
  REQUIRE(ct.ok());
  CHECK(ct->size() == state.ct_ram.size() - 1);
  for (const auto& e : *ct) CHECK(e.raw == state.ct_ram.at(static_cast<std::uint16_t>(e.id)));
  CHECK(notes == std::vector<std::string>{
                     "command table entry 200: listed as defined, but the drive answers its query "
                     "with state 00h and size 0: left out"});
  // The backup's report carries the same sentence.
  ops::BackupReport report;
  ops::BackupOptions bo;
  bo.report = &report;
  bo.layers = {false, false, false, false};
  bo.curves = false;
  auto cfg = ops::backup(*rig.client, bo, db::Database::empty());
  REQUIRE(cfg.ok());
  CHECK(std::find(report.notes.begin(), report.notes.end(), notes[0]) != report.notes.end());
  CHECK(report.empty_ct_form == std::optional<std::uint8_t>(0));
}

TEST_CASE("backup: the report says how many reads each value took and what that means",
          "[backup]") {
  SECTION("no checksum, no parity, automatic (as the tools' sessions): two agreeing reads") {
    client::ClientOptions co;
    co.agreeing_reads = 0;
    test::SimRig rig("commissioned-axis.json", co);
    const auto report = report_of(*rig.client);
    CHECK(report.reads_per_value == 2);
    REQUIRE_FALSE(report.notes.empty());
    CHECK(report.notes[0] ==
          "no checksum on this link: each value read twice; enable CRC on the drive (§15) to "
          "halve backup time");
  }
  SECTION("--agreeing-reads 3 without a checksum") {
    client::ClientOptions co;
    co.agreeing_reads = 3;
    test::SimRig rig("commissioned-axis.json", co);
    const auto report = report_of(*rig.client);
    CHECK(report.reads_per_value == 3);
    REQUIRE_FALSE(report.notes.empty());
    CHECK(report.notes[0] ==
          "no checksum on this link: each value read until 3 reads agreed (--agreeing-reads 3)");
  }
  SECTION("--agreeing-reads 1 (a bare client's default) without a checksum: the warning") {
    test::SimRig rig("commissioned-axis.json");
    const auto report = report_of(*rig.client);
    CHECK(report.reads_per_value == 1);
    REQUIRE_FALSE(report.notes.empty());
    CHECK(report.notes[0] ==
          "no checksum on this link and --agreeing-reads 1: a flipped bit in a value goes into "
          "the file undetected; enable CRC on the drive (§15)");
  }
  SECTION("a CRC: one read, nothing to say about it") {
    auto state = test::load_sim_drive("commissioned-axis.json")->state();
    state.checksum.mode = codec::ChecksumMode::crc_ccitt;
    test::FaultRig rig(std::make_shared<sim::Drive>(state));
    const auto report = report_of(*rig.client);
    CHECK(report.reads_per_value == 1);
    for (const auto& n : report.notes) CHECK(n.find("checksum") == std::string::npos);
  }
}

TEST_CASE("backup: a link that closes fails the backup", "[backup]") {
  test::FaultRig rig(test::load_sim_drive("commissioned-axis.json"));
  rig.sim->faults().schedule(3, sim::Fault::close_link());
  auto cfg = ops::backup(*rig.client, ops::BackupOptions{}, db::Database::empty());
  REQUIRE_FALSE(cfg.ok());
  CHECK(cfg.error().code == Errc::link_closed);
}

TEST_CASE("backup: a new capture has the drive's identity and nothing in scope", "[backup]") {
  test::SimRig rig("commissioned-axis.json");
  const auto cfg = ops::new_capture(*rig.client, db::Database::empty());
  CHECK(cfg.identity.macid == "0x11");
  CHECK(cfg.identity.tool_version == kToolVersion);
  CHECK(cfg.identity.upid_db_hash.empty());
  CHECK(cfg.identity.upid_db_version.empty());
  CHECK(cfg.scope.layers == std::array<bool, 4>{false, false, false, false});
  CHECK(cfg.scope.parameters == config::ParamSet::modified);
  CHECK_FALSE(cfg.scope.curves);
  CHECK_FALSE(cfg.scope.command_table);
  CHECK(rig.wire->tx.empty());
  const auto& db = db::test::fixture_db();
  const auto with_db = ops::new_capture(*rig.client, db);
  CHECK(with_db.identity.upid_db_hash == db.info().content_hash);
  CHECK(with_db.identity.upid_db_version == std::to_string(db.info().schema_version));
}

TEST_CASE("backup: values for people by the database, else by the recorded type, else raw",
          "[backup]") {
  const auto& none = db::Database::empty();
  CHECK(ops::display_value(none, 0x13A2, 16) == "16 (0010h)");
  CHECK(ops::display_value(none, 0x11F2, 0xFFFF, static_cast<std::uint8_t>(TypeCode::SInt16)) ==
        "-1");
  CHECK(ops::display_value(none, 0x11F2, 0xFFFF, static_cast<std::uint8_t>(TypeCode::UInt16)) ==
        "65535");
  // A code that is no §10 type: raw.
  CHECK(ops::display_value(none, 0x11F2, 5, 0xEE) == "5 (0005h)");
  const auto& db = db::test::fixture_db();
  CHECK(ops::display_value(db, 0x13A2, 16) == "16");
  CHECK(ops::display_value(db, 0x2008, 2) == "By Parameter (2)");
  CHECK(ops::display_value(db, 0x2200, 0xF6) == "-10 %");
  // The database's type wins over a recorded one.
  CHECK(ops::display_value(db, 0x2200, 0xF6, static_cast<std::uint8_t>(TypeCode::UInt8)) ==
        "-10 %");
}

TEST_CASE("backup: annotate fills names, units, types, defaults and scaled values", "[backup]") {
  config::DriveConfig cfg;
  cfg.layer(2) = {
      {0x13A2, 40, std::nullopt, std::nullopt, {}, {}, {}},
      {0x11F2, 0xFFFF, static_cast<std::uint8_t>(TypeCode::SInt16), std::nullopt, {}, {}, {}},
      {0x1EEE, 7, std::nullopt, std::nullopt, {}, {}, {}}};
  cfg.layer(3) = {{0x2200, 0xF6, std::nullopt, 3, {}, {}, {}}};
  ops::annotate(cfg, db::test::fixture_db());
  const auto& gain = cfg.layer(2)[0];
  CHECK(gain.name == "P Gain Position Controller Set A");
  CHECK(gain.type == std::optional<std::uint8_t>(static_cast<std::uint8_t>(TypeCode::UInt16)));
  CHECK(gain.default_value == std::optional<std::uint32_t>(16));
  CHECK(gain.scaled == "40");
  // Not in the database: shown by its recorded type; without one left alone.
  CHECK(cfg.layer(2)[1].name.empty());
  CHECK(cfg.layer(2)[1].scaled == "-1");
  CHECK(cfg.layer(2)[2].scaled.empty());
  CHECK_FALSE(cfg.layer(2)[2].type);
  const auto& trim = cfg.layer(3)[0];
  CHECK(trim.unit == "%");
  CHECK(trim.scaled == "-10 %");
  CHECK(trim.default_value == std::optional<std::uint32_t>(3));  // the recorded one stays
}

// LinRS §12.1: the command table entry of the manual's example (VAI Go To Pos).
TEST_CASE("LinRS §12.1 backup: command table entries decoded for the file through the database",
          "[backup]") {
  const ops::DatabaseCtDecoder decoder(db::test::fixture_db());
  auto v = decoder.decode(2, db::test::seed_ct_entry());
  REQUIRE(v);
  CHECK(v->summary ==
        "VAI Go To Pos, target 100 mm, max velocity 0.5 m/s, acceleration 2 m/s2, deceleration 2 "
        "m/s2");
  REQUIRE(v->params.size() == 4);
  CHECK(v->params[0].value == "100");
  CHECK(v->params[0].unit == "mm");
  CHECK(v->params[1].value == "0.5");
  CHECK(v->params[1].unit == "m/s");
  // Not decodable: an entry of the wrong size, or no catalogue to decode it with.
  CHECK_FALSE(decoder.decode(2, Bytes(40, 0)));
  const ops::DatabaseCtDecoder without(db::Database::empty());
  CHECK_FALSE(without.decode(2, db::test::seed_ct_entry()));
}

namespace {
// The requests of one message (main and sub ID) among what was sent.
std::size_t requests_of(const test::WireRecorder& w, std::uint8_t main, std::uint8_t sub) {
  std::size_t n = 0;
  codec::StreamDecoder dec;
  for (const auto& chunk : w.tx) {
    dec.feed(chunk);
    while (auto t = dec.next())
      if (t->ok() && t->value().main == main && t->value().sub == sub) ++n;
  }
  return n;
}
}  // namespace

TEST_CASE(
    "DCF p8, LinRS 3V27 §11-§12: backup of a B1100: no curves, command table or defaults asked, "
    "and said",
    "[backup][families]") {
  test::SimRig rig("commissioned-axis.json");
  rig.drive->state().options.family = "B1100";  // the simulator plays a B1100
  ops::BackupReport report;
  ops::BackupOptions bo;
  bo.family = families::find("B1100");
  bo.report = &report;
  auto cfg = ops::backup(*rig.client, bo, db::Database::empty());
  REQUIRE(cfg.ok());
  CHECK_FALSE(cfg->scope.curves);
  CHECK_FALSE(cfg->scope.command_table);
  CHECK(cfg->identity.product == "B1100");
  CHECK(cfg->scope.drive_lacks == std::vector<std::string>{"curves", "command_table"});
  CHECK(requests_of(*rig.wire, 0x04) == 0);        // LinRS 3V27 §11 "not on B1100"
  CHECK(requests_of(*rig.wire, 0x08) == 0);        // 3V27 §12
  CHECK(requests_of(*rig.wire, 0x05, 0x07) == 0);  // DCF p8: no stored defaults
  for (int layer = 1; layer <= 4; ++layer)
    for (const auto& p : cfg->layer(layer)) CHECK_FALSE(p.default_value);
  const auto& n = report.notes;
  CHECK(std::count(n.begin(), n.end(),
                   "B1100 has no curve group (LinRS 3V27 §11): curves not asked, not in the "
                   "file") == 1);
  CHECK(std::count(n.begin(), n.end(),
                   "B1100 has no command table group (LinRS 3V27 §12): command table not asked, "
                   "not in the file") == 1);
  CHECK(std::count(n.begin(), n.end(),
                   "B1100 stores no default values (DCF p8): defaults not asked") == 1);
}

TEST_CASE(
    "LinRS §16.1 backup of a drive that answers C3h for the curve and command table groups, "
    "family not named: it goes on without them, records and says so",
    "[backup][families]") {
  test::SimRig rig("commissioned-axis.json");
  rig.drive->state().options.family = "B1100";  // C3h undefined main ID on groups 04h and 08h
  ops::BackupReport report;
  ops::BackupOptions bo;  // no family named: taken for an E1100 until it answers
  bo.report = &report;
  auto cfg = ops::backup(*rig.client, bo, db::Database::empty());
  REQUIRE(cfg.ok());
  CHECK_FALSE(cfg->scope.curves);
  CHECK_FALSE(cfg->scope.command_table);
  CHECK(cfg->scope.drive_lacks == std::vector<std::string>{"curves", "command_table"});
  CHECK(cfg->curves.empty());
  CHECK(cfg->ct_entries.empty());
  CHECK(cfg->identity.product.empty());  // nobody named the family
  CHECK_FALSE(cfg->layer(2).empty());    // the parameters are all there
  // One curve probe (ID 1, until the reads agree), not one per curve ID.
  CHECK(requests_of(*rig.wire, 0x04, 0x08) >= 1);
  CHECK(requests_of(*rig.wire, 0x04, 0x08) <= 3);
  CHECK(config::validate(*cfg).ok());
  const auto& n = report.notes;
  CHECK(std::count(n.begin(), n.end(),
                   "the drive has no curve group (it answers C3h undefined message main ID, "
                   "LinRS §16.1): curves not in the file; --family B1100 says so up front") == 1);
  CHECK(std::count(n.begin(), n.end(),
                   "the drive has no command table group (it answers C3h undefined message main "
                   "ID, LinRS §16.1): the command table not in the file; --family B1100 says so "
                   "up front") == 1);
}

TEST_CASE(
    "LinRS §16.1 read_curves: a C3h answer to the first probe is the error, or no such group "
    "where the caller asks",
    "[backup][families]") {
  test::SimRig rig("commissioned-axis.json");
  rig.drive->state().options.family = "B1100";
  auto curves = ops::read_curves(*rig.client, 100, {}, "verify curves");
  REQUIRE_FALSE(curves.ok());
  CHECK(ops::no_such_group(curves.error()));
  CHECK(curves.error().code == ErrorClass::drive_refusal);
  bool none = false;
  auto again = ops::read_curves(*rig.client, 100, {}, "curves", &none);
  REQUIRE(again.ok());
  CHECK(none);
  CHECK(again->empty());
}

TEST_CASE("C1250 notes: a C1100's curves are probed up to its limit of 50, an E1100's to 100",
          "[backup][families]") {
  for (const char* name : {"C1100", "E1100"}) {
    INFO(name);
    client::ClientOptions one;
    one.agreeing_reads = 1;  // one read per probe: the count is the IDs probed
    test::SimRig rig("commissioned-axis.json", one);
    rig.drive->state().options.family = name;
    ops::BackupOptions bo;
    bo.family = families::find(name);
    bo.command_table = false;
    auto cfg = ops::backup(*rig.client, bo, db::Database::empty());
    REQUIRE(cfg.ok());
    CHECK(cfg->scope.curves);
    CHECK_FALSE(cfg->curves.empty());
    // §11 "read sizes" (04h 08h) once per probed ID, again for a curve that exists.
    const std::size_t probes = requests_of(*rig.wire, 0x04, 0x08);
    if (std::string(name) == "C1100") {
      CHECK(probes >= 50);
      CHECK(probes < 100);
    } else {
      CHECK(probes >= 100);
    }
  }
}

}  // namespace ops_test_backup
