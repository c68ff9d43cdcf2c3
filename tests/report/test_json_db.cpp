// The UPID database's rows as JSON (lib/report/json_db.cpp, `lmcfg db ... --json`,
// `db scan --json`, `db merge --json`): plain nlohmann::json, members sorted by
// name, every optional field null when the database does not know it.
#include <catch2/catch.hpp>
#include <string>

#include "db/database.hpp"
#include "ops/db_scan.hpp"
#include "report/json_reports.hpp"

// This file's own namespace: the test binary is a unity build (tests/CMakeLists.txt).
namespace report_test_json_db {

using namespace lmcfg;

namespace {

db::Provenance prov(const std::string& source, const std::string& file, int line) {
  return {source, file, line};
}

}  // namespace

TEST_CASE("json reports: db show of an unknown UPID and db merge, members sorted by name",
          "[report][json][db][json_db]") {
  CHECK(report::db_show_json(0x1234, {}).dump() ==
        R"({"definitions":[],"known":false,"note":"unknown to the database; the drive can be )"
        R"(asked","upid":"1234"})");
  ops::MergeReport m;
  m.profile = "e1100-fw-x";
  m.parameters_added = 3;
  CHECK(report::db_merge_json("upid-db", m).dump() ==
        R"({"into":"upid-db","parameters_added":3,"parameters_replaced":0,)"
        R"("profile":"e1100-fw-x","profile_replaced":false})");
}

TEST_CASE("json_db: a parameter with every field known, and one the database knows little of",
          "[json_db]") {
  db::Parameter p;
  p.upid = 0x13A2;
  p.layer = db::Layer::MC;
  p.name = "Position Lag Max";
  p.path = "Motion Control SW\\Monitoring\\Pos Lag";
  p.profiles = {"e1100-mc"};
  p.spec.type = db::TypeCode::SInt16;
  p.spec.unit = "mm";
  p.spec.scale = 0.5;
  p.spec.min = -100;
  p.spec.max = 100;
  p.spec.labels = {{0, "Off"}, {1, "On"}};
  p.default_value = 16;
  p.address_usage = db::AddressUsage{0x100F};
  p.comm = true;
  p.description = "a description";
  p.prov = prov("seed003 §10.1", "parameters.tsv", 12);
  CHECK(report::db_parameter_json(p).dump() ==
        R"({"address_usage":{"no_hash":true,"ram_read":true,"ram_write":true,"raw":"100F",)"
        R"("rom_read":true,"rom_write":true},"comm":true,"default":16,)"
        R"("description":"a description","enum":[{"label":"Off","raw":0},{"label":"On","raw":1}],)"
        R"("layer":"MC","max":100,"min":-100,"name":"Position Lag Max",)"
        R"("path":"Motion Control SW\\Monitoring\\Pos Lag","profiles":["e1100-mc"],)"
        R"("provenance":{"file":"parameters.tsv","line":12,"source":"seed003 §10.1"},)"
        R"("scale":0.5,"type":"SINT16","unit":"mm","upid":"13A2"})");

  db::Parameter bare;  // every profile, nothing but the UPID and its layer
  bare.upid = 0x0001;
  CHECK(report::db_parameter_json(bare).dump() ==
        R"({"address_usage":null,"comm":false,"default":null,"description":"","enum":[],)"
        R"("layer":"OS","max":null,"min":null,"name":"","path":"","profiles":["*"],)"
        R"("provenance":{"file":"","line":0,"source":""},"scale":null,"type":null,"unit":"",)"
        R"("upid":"0001"})");

  // The read-only usage bits each false on their own.
  db::Parameter ro = bare;
  ro.address_usage = db::AddressUsage{0x0005};
  CHECK(report::db_parameter_json(ro)["address_usage"].dump() ==
        R"({"no_hash":false,"ram_read":true,"ram_write":false,"raw":"0005","rom_read":true,)"
        R"("rom_write":false})");

  // db show of a known UPID: every definition (one per profile group), in order.
  db::Parameter other = p;
  other.profiles = {"e1100-old"};
  const auto shown = report::db_show_json(0x13A2, {&p, &other});
  CHECK(shown["known"] == true);
  CHECK_FALSE(shown.contains("note"));
  CHECK(shown["upid"] == "13A2");
  REQUIRE(shown["definitions"].size() == 2);
  CHECK(shown["definitions"][1]["profiles"] == nlohmann::json::array({"e1100-old"}));
  CHECK(report::db_parameters_json({&bare, &p}).dump() ==
        "[" + report::db_parameter_json(bare).dump() + "," + report::db_parameter_json(p).dump() +
            "]");
  CHECK(report::db_parameters_json({}).dump() == "[]");
}

TEST_CASE("json_db: error codes with their class and whether they are fatal", "[json_db]") {
  db::ErrorEntry e;
  e.domain = "mc";
  e.code = 0x000C;
  e.code_text = "000C";
  e.error_class = "Err";
  e.text = "Err: Pos Lag Standing Too Big";
  e.description = "The motor was not able to reach the target position.";
  e.action = "check the motor load";
  e.prov = prov("seed001 §10", "errors.tsv", 40);
  db::ErrorEntry f;
  f.domain = "mc";
  f.code = 0x0020;
  f.code_text = "0020";
  f.error_class = "Fatal Err";
  f.text = "Fatal Err: something";
  CHECK(report::db_errors_json({&e, &f}).dump() ==
        R"([{"action":"check the motor load","class":"Err","code":"000C",)"
        R"("description":"The motor was not able to reach the target position.","domain":"mc",)"
        R"("fatal":false,"provenance":{"file":"errors.tsv","line":40,"source":"seed001 §10"},)"
        R"("text":"Err: Pos Lag Standing Too Big"},)"
        R"({"action":"","class":"Fatal Err","code":"0020","description":"","domain":"mc",)"
        R"("fatal":true,"provenance":{"file":"","line":0,"source":""},)"
        R"("text":"Fatal Err: something"}])");
  CHECK(report::db_errors_json({}).dump() == "[]");
}

TEST_CASE("json_db: a motion command with its header pattern and parameters", "[json_db]") {
  db::MotionCommand c;
  c.master = 0x01;
  c.sub = 0x0;
  c.name = "VAI Go To Pos";
  c.products = "E1100";
  c.prov = prov("seed001 §4.3", "commands.tsv", 3);
  db::MotionParam target;
  target.index = 1;
  target.offset = 2;
  target.name = "Target Position";
  target.spec.type = db::TypeCode::SInt32;
  target.spec.unit = "mm";
  target.spec.scale = 0.0001;
  target.range_text = "-214748..214748";
  target.spec.min = -2147483648LL;
  target.spec.max = 2147483647LL;
  db::MotionParam scaled;
  scaled.index = 2;
  scaled.offset = 6;
  scaled.name = "Value";
  scaled.scaled = true;
  c.params = {target, scaled};
  CHECK(report::db_commands_json({c}).dump() ==
        R"([{"header":"010x","master":"01","name":"VAI Go To Pos","parameters":[)"
        R"({"index":1,"max":2147483647,"min":-2147483648,"name":"Target Position","offset":2,)"
        R"("provenance":{"file":"","line":0,"source":""},"range":"-214748..214748",)"
        R"("scale":0.0001,"scaled":false,"type":"SINT32","unit":"mm"},)"
        R"({"index":2,"max":null,"min":null,"name":"Value","offset":6,)"
        R"("provenance":{"file":"","line":0,"source":""},"range":"","scale":null,"scaled":true,)"
        R"("type":null,"unit":""}],"products":"E1100",)"
        R"("provenance":{"file":"commands.tsv","line":3,"source":"seed001 §4.3"},"sub":"0"}])");
  // The header pattern: master ID and sub ID, the count nibble as x (MC SW §4.1.1).
  db::MotionCommand h;
  h.master = 0x26;
  h.sub = 0x4;
  CHECK(report::db_commands_json({h})[0]["header"] == "264x");
  CHECK(report::db_commands_json({h})[0]["sub"] == "4");
  CHECK(report::db_commands_json({}).dump() == "[]");
}

TEST_CASE("json_db: DeviceNet commands and parameters with their value specs", "[json_db]") {
  db::DevicenetCommand c;
  c.id = 0x35;
  c.id_text = "0x35";
  c.direction = "set";
  c.name = "Set Controller P";
  c.table_name = "Set Controller P";
  c.range_text = "0 to 65535";
  c.unit_text = "2.3438 mA/mm";
  c.spec.min = 0;
  c.spec.max = 65535;
  c.spec.unit = "A/mm";
  c.spec.scale = 0.0023438;
  c.addressed = true;
  c.prov = prov("seed000 §5.2", "devicenet_commands.tsv", 7);
  const std::string spec_json =
      R"({"labels":[],"max":65535,"min":0,"scale":0.0023438,"type":null,"unit":"A/mm"})";
  CHECK(report::db_value_spec_json(c.spec).dump() == spec_json);
  CHECK(report::db_devicenet_command_json(c).dump() ==
        R"({"addressed":true,"description":"","direct":false,"direction":"set","id":"0x35",)"
        R"("name":"Set Controller P",)"
        R"("provenance":{"file":"devicenet_commands.tsv","line":7,"source":"seed000 §5.2"},)"
        R"("range":"0 to 65535","table_name":"Set Controller P","unit_text":"2.3438 mA/mm",)"
        R"("value":)" +
            spec_json + "}");
  CHECK(report::db_devicenet_commands_json({c, c}).size() == 2);
  CHECK(report::db_devicenet_commands_json({}).dump() == "[]");

  db::DevicenetParameter p;
  p.id = "DeviceNet\\Baudrate";
  p.name = "Baudrate";
  p.path = "DeviceNet\\Baudrate";
  p.spec.type = db::TypeCode::EnumDir16;
  p.spec.labels = {{0, "125 kBit/s"}, {1, "250 kBit/s"}};
  p.default_value = 0;
  p.comm = true;
  CHECK(report::db_devicenet_parameters_json({p}).dump() ==
        R"([{"comm":true,"default":0,"description":"","id":"DeviceNet\\Baudrate",)"
        R"("name":"Baudrate","path":"DeviceNet\\Baudrate",)"
        R"("provenance":{"file":"","line":0,"source":""},)"
        R"("value":{"labels":[{"label":"125 kBit/s","raw":0},{"label":"250 kBit/s","raw":1}],)"
        R"("max":null,"min":null,"scale":null,"type":"ENUM_DIR16","unit":""}}])");
  db::DevicenetParameter unknown;
  CHECK(report::db_devicenet_parameters_json({unknown})[0]["default"].is_null());
}

TEST_CASE("json_db: db info and db scan summaries", "[json_db]") {
  db::DbInfo i;
  i.path = "/usr/share/lmcfg/upid.db";
  i.schema_version = 4;
  i.content_hash = "fnv1a64:0123456789abcdef";
  i.built_from = "parameters.tsv errors.tsv";
  i.counts = {{"parameters", 120}, {"errors", 300}};
  CHECK(report::db_info_json(i).dump() ==
        R"({"built_from":"parameters.tsv errors.tsv","content_hash":"fnv1a64:0123456789abcdef",)"
        R"("counts":{"errors":300,"parameters":120},"path":"/usr/share/lmcfg/upid.db",)"
        R"("schema_version":4})");
  CHECK(report::db_info_json(db::DbInfo{}).dump() ==
        R"({"built_from":"","content_hash":"","counts":{},"path":"","schema_version":0})");

  ops::DbScanResult r;
  r.profile.id = "e1100-fw-x";
  r.source = "scanned from a drive: e1100-fw-x 2026-11-24 MACID 11h";
  r.rows.resize(5);
  r.named = 3;
  r.asked = 4;
  r.resumed = 1;
  r.refused = 2;
  r.per_layer = {1, 2, 0, 2};
  const std::string scan =
      R"({"asked":4,"file":"scan.tsv","layers":{"Appl":2,"Intf":0,"MC":2,"OS":1},"named":3,)"
      R"("profile":"e1100-fw-x","refused":2,"resumed":1,)"
      R"("source":"scanned from a drive: e1100-fw-x 2026-11-24 MACID 11h","telegrams":250,)"
      R"("upids":5})";
  CHECK(report::db_scan_json("scan.tsv", r, 250, "").dump() == scan);
  // Merged in the same run: where to.
  auto merged = report::db_scan_json("scan.tsv", r, 250, "upid-db");
  CHECK(merged["merged_into"] == "upid-db");
  merged.erase("merged_into");
  CHECK(merged.dump() == scan);
}

}  // namespace report_test_json_db
