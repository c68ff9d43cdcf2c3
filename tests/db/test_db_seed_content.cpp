// The UPID database's content against the seeds: row counts per table (so an
// edit of upid-db/*.tsv cannot silently drop rows; upid-db/EXTRACTION.md has
// the per-section counts) and spot values read off the seeds themselves.
#include <catch2/catch.hpp>
#include <map>

#include "db/ct_entry.hpp"
#include "db/database.hpp"

// This file's own namespace: the test binary is a unity build (tests/CMakeLists.txt).
namespace db_test_db_seed_content {

using namespace lmcfg;
using namespace lmcfg::db;

namespace {
const Database& real_db() {
  static auto db = Database::open(LMCFG_DB_PATH);
  REQUIRE(db.ok());
  return *db;
}
}  // namespace

TEST_CASE("upid-db: row counts of the extraction from seeds 001 and 003", "[db][seed]") {
  const auto& counts = real_db().info().counts;
  // 3 of the seeds; c1100, e1200, c1250 and a1100 for the public names (docs/upid-db.md).
  CHECK(counts.at("profiles") == 7);
  // 83 from seed 001 (6300h in layer Other), 10 from seed 003; 74 rows of public
  // names (public parameter names, docs/references.md: 86 of its 90 rows imported).
  CHECK(counts.at("parameters") == 167);
  CHECK(counts.at("errors") == 113);  // 85 MC codes 0000-008A, 8 LinRS states, 20 DeviceNet codes
  CHECK(counts.at("motion_commands") == 215);
  CHECK(counts.at("motion_command_params") == 469);
}

TEST_CASE("upid-db: seed 003 §10.1 13A2h is UINT16, min 0, max 65535, default 15", "[db][seed]") {
  const Parameter* p = real_db().find(0x13A2);
  REQUIRE(p != nullptr);
  CHECK(p->name == "P Gain Position Controller Set A");
  CHECK(p->layer == Layer::MC);
  REQUIRE(p->spec.type);
  CHECK(*p->spec.type == TypeCode::UInt16);
  CHECK(p->spec.min == 0);
  CHECK(p->spec.max == 65535);
  CHECK(p->default_value == 15);
  CHECK(p->prov.source.find("seed003") != std::string::npos);
}

TEST_CASE("upid-db: seed 001 §3.7 6300h lies outside the seed 003 §10.2 ranges, in layer Other",
          "[db][seed]") {
  const Parameter* p = real_db().find(0x6300);
  REQUIRE(p != nullptr);
  CHECK(p->layer == Layer::Other);
  CHECK(layer_name(p->layer) == "Other");
  CHECK_FALSE(layer_of_upid(0x6300).has_value());
  CHECK(p->prov.source == "seed001 §3.7");
  CHECK(p->name.empty());  // the seed names no parameter
  for (auto l : {Layer::OS, Layer::MC, Layer::Intf, Layer::Appl})
    for (const Parameter* q : real_db().in_layer(l)) CHECK(q->upid != 0x6300);
  // In layer Other besides it: 6085h, a B1100 trigger a public source names
  // (Smart-Vision-Works/linmot_client's LinMot-Talk manual copy), in the b1100-mc profile only.
  std::vector<std::uint16_t> other;
  for (const Parameter* q : real_db().in_layer(Layer::Other)) other.push_back(q->upid);
  CHECK(other == std::vector<std::uint16_t>{0x6085, 0x6300});
}

TEST_CASE("upid-db: seed 003 §10.2/§15 LinRS parameters are communication parameters",
          "[db][seed]") {
  for (std::uint16_t upid : {std::uint16_t{0x200E}, std::uint16_t{0x2012}, std::uint16_t{0x206C},
                             std::uint16_t{0x2076}}) {
    const Parameter* p = real_db().find(upid);
    REQUIRE(p != nullptr);
    CHECK(p->comm);
    CHECK(p->layer == Layer::Intf);
  }
  CHECK(real_db().find(0x2012)->path == "LinRS\\RS Config\\Baud Rate\\Baud Rate Parameter Def");
  // LinRS §15 "Baud Rate Parameter Definition" labels the value "38400 Bit/s";
  // §10.2 gives its raw value 00000008h.
  CHECK(real_db().find(0x2012)->format(8) == "38400 Bit/s (8)");
}

TEST_CASE("upid-db: error texts of seed 001 §10 and seed 003 §16.1", "[db][seed]") {
  const ErrorEntry* e = real_db().error("mc", 0x0001);
  REQUIRE(e != nullptr);
  CHECK(e->text == "Err: X4 Logic Supply Too Low");  // also the §14.2 capture's text
  REQUIRE(real_db().error("mc", 0x000C) != nullptr);
  CHECK(real_db().error("mc", 0x000C)->text == "Err: Pos Lag Standing Too Big");
  REQUIRE(real_db().error("linrs", 0xC8) != nullptr);
  CHECK(real_db().error("linrs", 0xC8)->text == "Parameter Unknown UPID");
}

TEST_CASE("upid-db: the motion command catalogue decodes seed 003 §12.1 entry 2", "[db][seed]") {
  const MotionCommand* c = real_db().motion_command(0x0100);
  REQUIRE(c != nullptr);
  CHECK(c->name == "VAI Go To Pos");
  REQUIRE(c->params.size() == 4);
  CHECK(c->params[0].offset == 2);
  CHECK(c->params[0].name == "Target Position");
}

// Seed 000, the DeviceNet supplement: counts as in upid-db/DEVICENET.md.
TEST_CASE("upid-db: seed 000 DeviceNet parameter tree, command set and error codes are all in",
          "[db][seed]") {
  const auto& db = real_db();
  CHECK(db.info().counts.at("devicenet_parameters") == 13);  // §3.1
  CHECK(db.info().counts.at("devicenet_commands") == 102);   // every row of §5.2 Table 5-1
  CHECK(db.errors("devicenet").size() == 20);  // §5.2 Get Error State (0Ah), 8100..8148
  REQUIRE(db.profile(kDevicenetProfile) != nullptr);
  CHECK(db.profile(kDevicenetProfile)->prov.source.rfind("seed000", 0) == 0);
  for (const auto& p : db.devicenet_parameters()) {
    INFO(p.id);
    CHECK(p.prov.source.rfind("seed000 §3.1", 0) == 0);
    CHECK_FALSE(p.spec.type);  // seed 000 states no type for any parameter: unknown, not invented
    CHECK_FALSE(p.default_value);
  }
  std::size_t addressed = 0, direct = 0, get = 0, set = 0;
  for (const auto& c : db.devicenet_commands()) {
    INFO(c.id_text);
    CHECK(c.prov.source.rfind("seed000 §5.2 Table 5-1", 0) == 0);
    addressed += c.addressed;
    direct += c.direct;
    get += c.direction == "get";
    set += c.direction == "set";
  }
  CHECK(addressed == 102);
  CHECK(direct == 57);
  CHECK(get == 45);
  CHECK(set == 44);
}

TEST_CASE(
    "upid-db: seed 000 spot values (§3.1 MACID Value, §5.2 Table 5-1 0x11 / 0x18 / 0x70, 0Ah "
    "codes)",
    "[db][seed]") {
  const auto& db = real_db();
  // §3.1 "MACID Value": DeviceNet\MACID\MACID Value, 0 to 63.
  const DevicenetParameter* macid = nullptr;
  for (const auto& p : db.devicenet_parameters())
    if (p.path == "DeviceNet\\MACID\\MACID Value") macid = &p;
  REQUIRE(macid != nullptr);
  CHECK(macid->spec.min == 0);
  CHECK(macid->spec.max == 63);
  CHECK(macid->comm);

  // Table 5-1: "0x11 Set Position Setpoint -32256 to +32256 0.01953 mm x x".
  const DevicenetCommand* c = db.devicenet_command(0x11);
  REQUIRE(c != nullptr);
  CHECK(c->name == "Set Position Setpoint");
  CHECK(c->direction == "set");
  CHECK(c->range_text == "-32256 to +32256");
  CHECK(c->spec.min == -32256);
  CHECK(c->spec.max == 32256);
  CHECK(c->spec.unit == "mm");
  CHECK(c->spec.scale == Approx(0.01953125));  // the detail's 19.53125 um
  CHECK(c->unit_text == "0.01953 mm");
  CHECK(c->addressed);
  CHECK(c->direct);
  // 0x18: the table and the detail disagree on the range, so min/max stay unknown.
  REQUIRE(db.devicenet_command(0x18) != nullptr);
  CHECK(db.devicenet_command(0x18)->range_text == "-32768 to +32767");
  CHECK_FALSE(db.devicenet_command(0x18)->spec.min);
  // 0x70: 0 to 7 with the Direct Out labels; Addressed module only.
  const DevicenetCommand* v = db.devicenet_command(0x70);
  REQUIRE(v != nullptr);
  REQUIRE(v->spec.labels.size() == 8);
  CHECK(v->spec.labels[0].label == "Actual Position");
  CHECK(v->spec.labels[7].label == "Current");
  CHECK_FALSE(v->direct);
  CHECK(db.devicenet_command(0x01) == nullptr);  // not in Table 5-1
  // 0Ah response: "8100 Application needs DN servo controller ... 8148 CAN BOFF error".
  REQUIRE(db.error("devicenet", 0x8100) != nullptr);
  CHECK(db.error("devicenet", 0x8100)->text == "Application needs DN servo controller");
  REQUIRE(db.error("devicenet", 0x8148) != nullptr);
  CHECK(db.error("devicenet", 0x8148)->text == "CAN BOFF error");
}

TEST_CASE("upid-db: seed 001 §4.3 ranges and Scaled written in the unit column are kept",
          "[db][seed]") {
  // §4.3.41 040xh Time Curve With Default Parameters: "Curve ID UInt16 1..100".
  const MotionCommand* curve = real_db().motion_command(0x0400);
  REQUIRE(curve != nullptr);
  REQUIRE(curve->params.size() == 1);
  CHECK(curve->params[0].range_text == "1..100");
  CHECK(curve->params[0].spec.min == 1);
  CHECK(curve->params[0].spec.max == 100);
  CHECK_FALSE(curve->params[0].scaled);
  // §4.3.140 200xh Command Table: Start Command Table: "Command Table ID UInt16 1..255".
  const MotionCommand* ct = real_db().motion_command(0x2000);
  REQUIRE(ct != nullptr);
  CHECK(ct->params.at(0).range_text == "1..255");
  CHECK(ct->params.at(0).spec.max == 255);
  // §4.3.143 208xh: "Parameter Offset UInt16 0..3Eh".
  const MotionCommand* mod = real_db().motion_command(0x2080);
  REQUIRE(mod != nullptr);
  CHECK(mod->params.at(1).range_text == "0..3Eh");
  CHECK(mod->params.at(1).spec.max == 0x3E);
  // §4.3.77 098xh VAI 16 Bit Go To Pos After Actual Command: "Target Position SInt16 Scaled".
  const MotionCommand* vai16 = real_db().motion_command(0x0980);
  REQUIRE(vai16 != nullptr);
  CHECK(vai16->params.at(0).scaled);
  CHECK(vai16->params.at(0).spec.unit.empty());
  std::size_t scaled = 0, ranged = 0;
  for (const auto& c : real_db().motion_commands())
    for (const auto& p : c.params) {
      scaled += p.scaled ? 1 : 0;
      ranged += p.range_text.empty() ? 0 : 1;
    }
  CHECK(scaled == 66);  // every "Scaled" of §4.3
  CHECK(ranged == 84);  // 39 x 1..255, 38 x 1..100, 5 x 0.., 2 x 0..3Eh
}

TEST_CASE("upid-db: seed 001 §10 error classes are a field, fatal ones say so", "[db][seed]") {
  CHECK(real_db().error("mc", 0x0001)->error_class == "Err");
  CHECK_FALSE(real_db().error("mc", 0x0001)->fatal());
  CHECK(real_db().error("mc", 0x000A)->error_class == "Fatal Err");  // X12 Signals Missing
  CHECK(real_db().error("mc", 0x000A)->fatal());
  CHECK(real_db().error("mc", 0x0064)->error_class == "Cfg Err (Fatal)");
  CHECK(real_db().error("mc", 0x0064)->fatal());
  CHECK(real_db().error("mc", 0x0000)->error_class.empty());  // "No Error"
  std::map<std::string, int> per_class;
  for (const auto& e : real_db().all_errors())
    if (e.domain == "mc") ++per_class[e.error_class];
  CHECK(per_class == std::map<std::string, int>{{"", 1},
                                                {"Cfg Err", 5},
                                                {"Cfg Err (Fatal)", 4},
                                                {"Err", 56},
                                                {"Fatal Err", 5},
                                                {"Runtime Err", 1},
                                                {"Setup Err", 2},
                                                {"User Err", 11}});
}

TEST_CASE("upid-db: public parameter names, each in the profile its source names",
          "[db][seed][families]") {
  const Database& db = real_db();
  // Seed 001 §6 says 13A6h is the maximal current of position controller set A
  // on E1100; remcohn/linUDP (C1250, constants named E1100_*) names it with
  // type and unit. The sources agree: the E1100 row carries the name.
  const Parameter* maxi = db.find(0x13A6);
  REQUIRE(maxi);
  CHECK(maxi->profiles == std::vector<std::string>{"e1100-mc-linrs"});
  CHECK(maxi->name == "Position controller maximal current (MAX_I)");
  CHECK(maxi->spec.unit == "A");
  CHECK(maxi->prov.source.find("seed001 §4.3.110") == 0);
  CHECK(maxi->prov.source.find("public: remcohn/linUDP linUDP.h (seen for: C1250") !=
        std::string::npos);

  // A C1250 name never labels a value of the reference profile (E1100).
  CHECK(db.find(0x1450) == nullptr);
  const Parameter* run = db.find(0x1450, "c1250-mc-linudp");
  REQUIRE(run);
  CHECK(run->name == "Run Mode (Run Mode Selection)");
  CHECK(run->prov.source.find("Smart-Vision-Works/linmot_client") != std::string::npos);
  CHECK(run->prov.source.find("remcohn/linUDP") != std::string::npos);  // the second source
  // A C1250 name for a UPID the seed already names does not replace the seed's.
  CHECK(db.find(0x13A2)->name == "P Gain Position Controller Set A");
  CHECK(db.find(0x13A2, "c1250-mc-linudp")->name == "Position controller P gain (PID_P)");

  // B1100 numbers differ (3V27 p26): 6085h is B1100's only.
  CHECK(db.find(0x6085) == nullptr);
  REQUIRE(db.find(0x6085, "b1100-mc"));
  CHECK(db.find(0x6085, "b1100-mc")->layer == Layer::Other);

  // The checksum UPID of 3V27 §4.4 for the LinRS families, a communication parameter.
  const Parameter* chk = db.find(0x2080);
  REQUIRE(chk);
  CHECK(chk->comm);
  CHECK(chk->profiles ==
        std::vector<std::string>{"e1100-mc-linrs", "c1100-mc-linrs", "e1200-mc-linrs"});

  // One UPID, three families, three sources.
  CHECK(db.find_all(0x1B8D).size() == 3);
  CHECK(db.find(0x1B8D)->name == "Actual Position");
  CHECK(db.find(0x1B8D, "e1200-mc-linrs")->name ==
        "Actual Position (LinRS MC Response Config Channel 1 UPID)");

  // Rows whose source names no family are not imported (docs/upid-db.md).
  CHECK(db.find_all(0x0078).empty());
  CHECK(db.find_all(0x173E).empty());
}

}  // namespace db_test_db_seed_content
