// The DeviceNet restore's plan as restore report items (devicenet_plan_json):
// the shape of the LinRS restore's steps with a `devicenet_set` step per Set
// command (docs/json-reports.md), from a plan of seed 000 Table 5-1 values.
#include <catch2/catch.hpp>

#include "db/database.hpp"
#include "ops/devicenet_restore.hpp"
#include "test_config_support.hpp"

// This file's own namespace: the test binary is a unity build (tests/CMakeLists.txt).
namespace ops_test_devicenet_restore {

using namespace lmcfg;
using namespace lmcfg::config::testing;

namespace {

const db::Database& real_db() {
  static auto db = db::Database::open(LMCFG_DB_PATH);
  REQUIRE(db.ok());
  return *db;
}

}  // namespace

TEST_CASE(
    "DeviceNet §5.2 Table 5-1: a plan of one Set command as restore report items, with raw and "
    "scaled values",
    "[devicenet][restore][json]") {
  const auto file = devicenet_capture();  // motor A's Controller P at 1000
  auto current = file;
  for (auto& v : current.devicenet->values)
    if (v.motor == 0 && v.command == 0x34) v.raw = 2000;
  auto plan = ops::plan_devicenet_restore(file, current, real_db());
  REQUIRE(plan.problems.empty());
  plan.notes = {"not read: controller: Encoder 1 Offset (66h)"};
  const auto j = ops::devicenet_plan_json(plan);
  // DeviceNet §5.2 "Command: Set Controller P (35h)": "Detail unit 2.3438
  // mA/mm": 2000 -> 4.6876 A/mm, 1000 -> 2.3438 A/mm.
  const nlohmann::ordered_json want = {
      {"problems", nlohmann::ordered_json::array()},
      {"nothing_to_do", false},
      {"steps",
       {{{"step", 1},
         {"action", "devicenet_set"},
         {"motor", "A"},
         {"command", "35h"},
         {"name", "motor A: Controller P (34h)"},
         {"old", {{"raw", 2000}, {"display", "4.6876 A/mm (raw 2000)"}}},
         {"new", {{"raw", 1000}, {"display", "2.3438 A/mm (raw 1000)"}}},
         {"text",
          "motor A: Controller P (34h): 4.6876 A/mm (raw 2000) -> 2.3438 A/mm (raw 1000)"}}}},
      {"losses", nlohmann::ordered_json::array()},
      {"skipped", nlohmann::ordered_json::array()},
      {"skipped_incompatible", nlohmann::ordered_json::array()},
      {"notes", {"not read: controller: Encoder 1 Offset (66h)", ops::kRuntimeNote}},
      {"devicenet", {{"unchanged", 3}}}};
  CHECK(j.dump(1) == want.dump(1));
}

TEST_CASE("DeviceNet §5.2 a refused plan and a plan with nothing to write as report items",
          "[devicenet][restore][json]") {
  const auto file = devicenet_capture();
  const auto same = ops::devicenet_plan_json(ops::plan_devicenet_restore(file, file, real_db()));
  CHECK(same["nothing_to_do"] == true);
  CHECK(same["steps"].empty());
  CHECK(same["devicenet"]["unchanged"] == 4);
  config::DriveConfig linrs;  // a LinRS capture: no devicenet section
  const auto refused =
      ops::devicenet_plan_json(ops::plan_devicenet_restore(linrs, file, real_db()));
  CHECK(refused["problems"] == nlohmann::ordered_json{"the file is a LinRS drive capture, not a "
                                                      "DeviceNet controller's"});
  CHECK(refused["nothing_to_do"] == false);
  CHECK(refused["steps"].empty());
}

}  // namespace ops_test_devicenet_restore
