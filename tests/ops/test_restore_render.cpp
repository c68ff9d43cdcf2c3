// The restore plan for people and as JSON items (lib/ops/restore_render.cpp),
// on plans built here: a refused plan, nothing to do (with and without
// skipped values), steps with losses, skips and notes, and every step kind's
// JSON members (docs/json-reports.md "lmcfg restore --json").
#include <catch2/catch.hpp>

#include "ops/restore.hpp"

// This file's own namespace: the test binary is a unity build (tests/CMakeLists.txt).
namespace ops_test_restore_render {

using namespace lmcfg;
using Action = ops::PlanStep::Action;

namespace {

ops::PlanStep step(Action a, std::string text, std::uint32_t key = 0) {
  ops::PlanStep s;
  s.action = a;
  s.key = key;
  s.text = std::move(text);
  return s;
}

ops::PlanStep write_rom(int layer, std::uint16_t upid, std::optional<std::uint32_t> old,
                        std::uint32_t value, ops::WriteReason why) {
  ops::PlanStep s = step(Action::write_rom, "write MC 13A2h P Gain: 16 -> 40", upid);
  s.layer = layer;
  s.value = value;
  s.old_value = old;
  s.old_display = old ? std::to_string(*old) : "";
  s.new_display = std::to_string(value);
  s.name = "P Gain";
  s.reason = why;
  return s;
}

ops::SkippedValue skipped(ops::SkippedValue::Kind kind, int layer, std::uint32_t key,
                          std::string name, ops::Incompatibility r, std::string why,
                          std::string text) {
  ops::SkippedValue v;
  v.kind = kind;
  v.layer = layer;
  v.key = key;
  v.name = std::move(name);
  v.reason = r;
  v.why = std::move(why);
  v.text = std::move(text);
  return v;
}

}  // namespace

TEST_CASE("restore render: every step action has its JSON name", "[restore_render]") {
  const std::vector<std::pair<Action, std::string>> names = {
      {Action::stop_mc, "stop_mc"},
      {Action::default_layer, "default_layer"},
      {Action::write_rom, "write_rom"},
      {Action::delete_all_ct, "delete_all_ct"},
      {Action::write_ct, "write_ct"},
      {Action::save_ct, "save_ct"},
      {Action::delete_all_curves, "delete_all_curves"},
      {Action::write_curve, "write_curve"},
      {Action::save_curves, "save_curves"},
      {Action::start_mc, "start_mc"},
      {Action::reset, "reset"},
      {Action::delete_ct, "delete_ct"},
      {Action::delete_curve, "delete_curve"},
  };
  for (const auto& [a, name] : names) CHECK(ops::action_name(a) == name);
}

TEST_CASE("restore render: a refused plan lists its problems and says nothing is written",
          "[restore_render]") {
  ops::Plan p;
  p.problems = {"MC 1037h: UPID does not exist on the target (not in its MC UPID list, §10.3)",
                "curve 101: ID outside 1..100"};
  p.steps.push_back(step(Action::stop_mc, "stop MC"));  // never shown for a refused plan
  CHECK(ops::render_plan(p) ==
        "restore refused: 2 problem(s), nothing written:\n"
        "  problem: MC 1037h: UPID does not exist on the target (not in its MC UPID list, "
        "§10.3)\n"
        "  problem: curve 101: ID outside 1..100\n");
  p.skipped_incompatible.push_back(skipped(ops::SkippedValue::Kind::curve, 0, 101, "Lift",
                                           ops::Incompatibility::curve_id_limit,
                                           "ID outside 1..100",
                                           "curve 101 'Lift': ID outside "
                                           "1..100"));
  CHECK(ops::render_plan(p) ==
        "restore refused: 2 problem(s), nothing written:\n"
        "  problem: MC 1037h: UPID does not exist on the target (not in its MC UPID list, "
        "§10.3)\n"
        "  problem: curve 101: ID outside 1..100\n"
        "skipped (the target cannot take them):\n"
        "  curve 101 'Lift': ID outside 1..100\n");
  const auto j = ops::plan_json(p);
  CHECK(j["problems"].size() == 2);
  CHECK(j["nothing_to_do"] == false);
}

TEST_CASE("restore render: nothing to do, with and without skipped values", "[restore_render]") {
  ops::Plan p;
  CHECK(ops::render_plan(p) ==
        "plan: nothing to do: the target already matches the file (no write, MC keeps running)\n");
  CHECK(ops::render_skipped_incompatible(p).empty());
  p.notes.push_back("curves: the target holds none, nor does the file");
  CHECK(ops::render_plan(p) ==
        "plan: nothing to do: the target already matches the file (no write, MC keeps running)\n"
        "  note: curves: the target holds none, nor does the file\n");
  p.notes.clear();
  p.skipped_incompatible.push_back(
      skipped(ops::SkippedValue::Kind::parameter, 2, 0x1037, "", ops::Incompatibility::upid_absent,
              "UPID does not exist on the target (not in its MC UPID list, §10.3)",
              "MC 1037h: UPID does not exist on the target (not in its MC UPID list, §10.3)"));
  CHECK(ops::render_skipped_incompatible(p) ==
        "skipped (the target cannot take them):\n"
        "  MC 1037h: UPID does not exist on the target (not in its MC UPID list, §10.3)\n");
  CHECK(ops::render_plan(p) ==
        "plan: nothing to do: the target already matches the file except the skipped values "
        "(no write, MC keeps running)\n"
        "skipped (the target cannot take them):\n"
        "  MC 1037h: UPID does not exist on the target (not in its MC UPID list, §10.3)\n");
  const auto j = ops::plan_json(p);
  CHECK(j["nothing_to_do"] == true);
  CHECK(j["steps"].is_array());
  CHECK(j["steps"].empty());
}

TEST_CASE("restore render: steps numbered, then losses, skips and notes", "[restore_render]") {
  ops::Plan p;
  p.steps = {step(Action::stop_mc, "stop MC (§13.3)"),
             write_rom(2, 0x13A2, 16, 40, ops::WriteReason::differs),
             step(Action::write_curve, "write curve 3 'Lift'", 3),
             step(Action::save_curves, "save curves to flash"), step(Action::reset, "reset")};
  p.write_telegrams = 61;
  p.losses = {"curve 3 'Lift' replaced by the file's 'Lift'"};
  p.skipped = {"Intf 2076h: communication value kept (--include-comm writes it)"};
  p.notes = {"MC: 2 leftover(s) go back to their defaults"};
  CHECK(ops::render_plan(p) ==
        "plan: 5 step(s), about 61 write telegram(s)\n"
        "  1. stop MC (§13.3)\n"
        "  2. write MC 13A2h P Gain: 16 -> 40\n"
        "  3. write curve 3 'Lift'\n"
        "  4. save curves to flash\n"
        "  5. reset\n"
        "  the target loses: curve 3 'Lift' replaced by the file's 'Lift'\n"
        "  skip: Intf 2076h: communication value kept (--include-comm writes it)\n"
        "  note: MC: 2 leftover(s) go back to their defaults\n");
}

TEST_CASE("restore render: plan_json's items per step kind and skipped value kind",
          "[restore_render]") {
  ops::Plan p;
  auto def = step(Action::default_layer, "default MC (§10.4)");
  def.layer = 2;
  p.steps = {step(Action::stop_mc, "stop MC"),
             def,
             write_rom(2, 0x13A2, 16, 40, ops::WriteReason::again_after_defaulting),
             write_rom(3, 0x2076, std::nullopt, 0x11, ops::WriteReason::kept_communication),
             step(Action::write_ct, "write command table entry 5", 5),
             step(Action::delete_ct, "delete command table entry 6", 6),
             step(Action::write_curve, "write curve 3", 3),
             step(Action::delete_curve, "delete curve 4", 4),
             step(Action::save_ct, "save the command table to flash")};
  p.losses = {"command table entry 6 'Home'"};
  p.skipped = {"a skip"};
  p.notes = {"a note"};
  p.skipped_incompatible = {
      skipped(ops::SkippedValue::Kind::curve, 0, 101, "Lift", ops::Incompatibility::curve_id_limit,
              "ID outside 1..100", "curve 101 'Lift': ID outside 1..100"),
      skipped(ops::SkippedValue::Kind::ct_entry, 0, 7, "Home", ops::Incompatibility::ct_entry_size,
              "entry size 32 differs from the target's 64",
              "command table entry 7: entry size 32 differs from the target's 64")};
  const auto j = ops::plan_json(p);
  CHECK(j.dump() == nlohmann::ordered_json::parse(R"json({
  "problems": [],
  "nothing_to_do": false,
  "steps": [
    {"step": 1, "action": "stop_mc", "text": "stop MC"},
    {"step": 2, "action": "default_layer", "layer": "MC", "text": "default MC (§10.4)"
},
    {"step": 3, "action": "write_rom", "layer": "MC", "upid": "13A2", "name": "P Gain",
     "old": {"raw": 16, "display": "16"}, "new": {"raw": 40, "display": "40"},
     "why": "again after defaulting", "text": "write MC 13A2h P Gain: 16 -> 40"},
    {"step": 4, "action": "write_rom", "layer": "Intf", "upid": "2076", "name": "P Gain",
     "old": null, "new": {"raw": 17, "display": "17"},
     "why": "kept communication value", "text": "write MC 13A2h P Gain: 16 -> 40"},
    {"step": 5, "action": "write_ct", "id": 5, "text": "write command table entry 5"},
    {"step": 6, "action": "delete_ct", "id": 6, "text": "delete command table entry 6"},
    {"step": 7, "action": "write_curve", "id": 3, "text": "write curve 3"},
    {"step": 8, "action": "delete_curve", "id": 4, "text": "delete curve 4"},
    {"step": 9, "action": "save_ct", "text": "save the command table to flash"}
  ],
  "losses": ["command table entry 6 'Home'"],
  "skipped": ["a skip"],
  "skipped_incompatible": [
    {"curve": 101, "name": "Lift", "reason_code": "curve_id_limit",
     "reason": "ID outside 1..100"},
    {"ct_entry": 7, "name": "Home", "reason_code": "ct_entry_size",
     "reason": "entry size 32 differs from the target's 64"}
  ],
  "notes": ["a note"],
  "kept": []
})json")
                        .dump());
}

TEST_CASE("restore render: the values the restore keeps, in the text plan and in JSON",
          "[restore_render][matching]") {
  ops::Plan p;
  ops::DiffItem baud;
  baud.kind = ops::DiffItem::Kind::parameter;
  baud.layer = 3;
  baud.key = 0x2012;
  baud.name = "Baud Rate Parameter Def";
  baud.a = "16";
  baud.b = "8";
  p.kept.push_back(ops::KeptValue{baud, ops::KeptBy::communication});
  CHECK(ops::render_plan(p) ==
        "plan: nothing to do: the target already matches the file except the values it keeps (no "
        "write, MC keeps running)\n"
        "  stays different: Intf 2012h Baud Rate Parameter Def: file 16, drive 8 (a "
        "communication setting: a restore keeps the drive's own value, so that the drive keeps "
        "answering on its line as it does now)\n");
  const auto j = ops::plan_json(p);
  REQUIRE(j["kept"].size() == 1);
  CHECK(j["kept"][0]["upid"] == "2012");
  CHECK(j["kept"][0]["configuration"] == "16");
  CHECK(j["kept"][0]["drive"] == "8");
  CHECK(j["kept"][0]["text"] == "Intf 2012h Baud Rate Parameter Def: file 16, drive 8");
}

}  // namespace ops_test_restore_render
