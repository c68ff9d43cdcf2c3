// Whether the target still reads as a plan found it (ops::target_change): the
// check behind lmcfg serve's plan/execute, which executes a plan made earlier
// only while the drive reads the same.
#include <catch2/catch.hpp>

#include "ops/restore.hpp"

// This file's own namespace: the test binary is a unity build (tests/CMakeLists.txt).
namespace ops_test_restore_target {

using namespace lmcfg;

namespace {

ops::Plan seen_plan() {
  ops::Plan p;
  p.target.layers[0] = std::vector<client::ModifiedParam>{{0x1003, 7}};
  p.target.layers[2] = std::vector<client::ModifiedParam>{{0x2076, 0x11}};
  p.target.ct_entries = std::map<std::uint32_t, Bytes>{{3, Bytes{1, 2, 3}}};
  p.target.curves = std::vector<ops::TargetSeen::CurveSeen>{{1, Bytes{9, 9}, 16, std::nullopt}};
  ops::PlanStep w;
  w.action = ops::PlanStep::Action::write_rom;
  w.layer = 1;
  w.key = 0x1003;
  w.value = 8;
  w.old_value = 7;
  p.steps = {w};
  return p;
}

}  // namespace

TEST_CASE("restore target: two plans that found the same target", "[restore_target]") {
  const auto a = seen_plan();
  CHECK(ops::target_change(a, seen_plan()).empty());
  // A step's text is for people: it is not part of what the target reads.
  auto b = seen_plan();
  b.steps[0].text = "write 1003h";
  CHECK(ops::target_change(a, b).empty());
}

TEST_CASE("restore target: each part of the target that changed is named", "[restore_target]") {
  const auto a = seen_plan();
  auto b = seen_plan();
  b.target.layers[2]->push_back({0x2012, 8});
  CHECK(ops::target_change(a, b) == "the Intf layer's modified parameters");

  b.target.ct_entries->at(3) = Bytes{1, 2, 4};
  CHECK(ops::target_change(a, b) == "the Intf layer's modified parameters and the command table");

  b.target.curves->at(0).data_size = 20;
  b.target.layers[0]->clear();
  CHECK(ops::target_change(a, b) ==
        "the OS layer's modified parameters, the Intf layer's modified parameters, the command "
        "table and the curves");

  // A layer one plan read and the other did not is a change too.
  auto c = seen_plan();
  c.target.layers[3] = std::vector<client::ModifiedParam>{};
  CHECK(ops::target_change(a, c) == "the Appl layer's modified parameters");
}

TEST_CASE("restore target: a curve's data counts only where both plans read it",
          "[restore_target]") {
  auto a = seen_plan();
  auto b = seen_plan();
  b.target.curves->at(0).data = Bytes{5, 6};
  CHECK(ops::target_change(a, b).empty());  // only one plan read the data
  a.target.curves->at(0).data = Bytes{5, 6};
  CHECK(ops::target_change(a, b).empty());
  a.target.curves->at(0).data = Bytes{5, 7};
  CHECK(ops::target_change(a, b) == "the curves");

  auto c = seen_plan();
  c.target.curves->at(0).info = Bytes{9, 8};
  CHECK(ops::target_change(seen_plan(), c) == "the curves");
  c = seen_plan();
  c.target.curves->push_back({2, Bytes{}, 0, std::nullopt});
  CHECK(ops::target_change(seen_plan(), c) == "the curves");
  c = seen_plan();
  c.target.curves.reset();
  CHECK(ops::target_change(seen_plan(), c) == "the curves");
}

TEST_CASE("restore target: the same lists but other values under the steps", "[restore_target]") {
  const auto a = seen_plan();
  // The ROM value a write would replace changed (the modified lists hold RAM values).
  auto b = seen_plan();
  b.steps[0].old_value = 6;
  CHECK(ops::target_change(a, b) == "the values the plan would write over");
  b = seen_plan();
  b.steps.push_back(b.steps[0]);
  CHECK(ops::target_change(a, b) == "the values the plan would write over");
  // A plan refused now and not then.
  b = seen_plan();
  const std::string refused = "the target has no UPID 1003h";
  b.problems.push_back(refused);
  CHECK(ops::target_change(a, b) == "the values the plan would write over");
  // The steps are compared only when the reads are the same: the reads name the change.
  b.target.ct_entries->clear();
  CHECK(ops::target_change(a, b) == "the command table");
}

}  // namespace ops_test_restore_target
