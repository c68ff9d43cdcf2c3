// Verify (lib/ops/restore_verify.cpp): the written scope read back with
// backup's readers and compared with what the plan expects, against a
// simulated drive in process; every kind of mismatch with its exact message.
#include <catch2/catch.hpp>

#include "client/client.hpp"
#include "db/database.hpp"
#include "e2e_support.hpp"
#include "ops/backup.hpp"
#include "ops/restore.hpp"

// This file's own namespace: the test binary is a unity build (tests/CMakeLists.txt).
namespace ops_test_restore_verify {

using namespace lmcfg;

namespace {

// The target already holds the file backed up from it: the plan expects it.
ops::Plan plan_on(test::SimRig& rig) {
  auto file = ops::backup(*rig.client, ops::BackupOptions{}, db::Database::empty());
  REQUIRE(file.ok());
  auto plan = ops::plan_restore(*rig.client, *file, db::Database::empty(), ops::RestoreOptions{});
  REQUIRE(plan.ok());
  REQUIRE(plan->nothing_to_do());
  return std::move(plan).value();
}

}  // namespace

TEST_CASE("seed003 §10.2 §11 §12 verify: a drive that holds the file reads back without mismatch",
          "[restore][verify]") {
  test::SimRig rig("commissioned-axis.json");
  const auto plan = plan_on(rig);
  auto v = ops::verify_restore(*rig.client, plan, ops::RestoreOptions{});
  REQUIRE(v.ok());
  for (const auto& m : v->mismatches) UNSCOPED_INFO(m);
  CHECK(v->ok());
  CHECK_FALSE(v->ct_differs);
  CHECK_FALSE(v->curves_differ);
}

TEST_CASE("seed003 §10.2 verify: a parameter that differs, one at its default, one not in the file",
          "[restore][verify]") {
  test::SimRig rig("commissioned-axis.json");
  const auto plan = plan_on(rig);
  auto& params = rig.drive->state().params;
  // 0010h: the file has 5; back at its default 0 the drive no longer lists it
  // and its ROM value is read. 0020h: at its default in the file, modified now.
  params.at(0x0010).rom = params.at(0x0010).def;
  params.at(0x0020).rom = params.at(0x0020).def + 1;
  auto v = ops::verify_restore(*rig.client, plan, ops::RestoreOptions{});
  REQUIRE(v.ok());
  CHECK(v->mismatches ==
        std::vector<std::string>{
            "OS 0010h: expected 5, drive has " + std::to_string(params.at(0x0010).def),
            "OS 0020h: modified on the drive (" + std::to_string(params.at(0x0020).rom) +
                ") but not in the file"});
  CHECK_FALSE(v->ct_differs);
  CHECK_FALSE(v->curves_differ);
}

TEST_CASE("seed003 §11 verify: a curve missing, one added and one whose blocks differ",
          "[restore][verify]") {
  test::SimRig rig("commissioned-axis.json");
  const auto plan = plan_on(rig);
  auto& curves = rig.drive->state().curves_ram;
  REQUIRE(curves.size() >= 2);
  const std::uint16_t first = curves.begin()->first, second = std::next(curves.begin())->first;
  REQUIRE(curves.count(99) == 0);
  curves[99] = curves.at(first);
  curves.erase(first);
  curves.at(second).data.back() ^= 0x01;
  auto v = ops::verify_restore(*rig.client, plan, ops::RestoreOptions{});
  REQUIRE(v.ok());
  CHECK(v->mismatches ==
        std::vector<std::string>{"curve " + std::to_string(first) + ": missing on the drive",
                                 "curve " + std::to_string(second) + ": blocks differ",
                                 "curve 99: on the drive but not in the file"});
  CHECK(v->curves_differ);
  CHECK_FALSE(v->ct_differs);
}

TEST_CASE("seed003 §12 verify: command table entries that differ and a count that differs",
          "[restore][verify]") {
  test::SimRig rig("commissioned-axis.json");
  const auto plan = plan_on(rig);
  auto& ct = rig.drive->state().ct_ram;
  REQUIRE(ct.size() >= 2);
  const std::size_t n = ct.size();
  const std::uint16_t first = ct.begin()->first, last = ct.rbegin()->first;
  ct.at(first).at(0) ^= 0x01;
  ct.erase(last);
  auto v = ops::verify_restore(*rig.client, plan, ops::RestoreOptions{});
  REQUIRE(v.ok());
  CHECK(v->mismatches == std::vector<std::string>{
                             "command table: drive defines " + std::to_string(n - 1) +
                                 " entries, the file " + std::to_string(n),
                             "command table entry " + std::to_string(first) + ": bytes differ"});
  CHECK(v->ct_differs);
  CHECK_FALSE(v->curves_differ);
}

}  // namespace ops_test_restore_verify
