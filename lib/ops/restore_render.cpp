// Restore: the plan for people (render_plan) and as structured items
// (plan_json, documented in docs/restore.md). See restore.hpp.
#include "common/bytes.hpp"
#include "common/layers.hpp"
#include "ops/restore.hpp"
#include "ops/restore_internal.hpp"

namespace lmcfg::ops {

const char* action_name(PlanStep::Action a) {
  using A = PlanStep::Action;
  switch (a) {
    case A::stop_mc:
      return "stop_mc";
    case A::default_layer:
      return "default_layer";
    case A::write_rom:
      return "write_rom";
    case A::delete_all_ct:
      return "delete_all_ct";
    case A::write_ct:
      return "write_ct";
    case A::save_ct:
      return "save_ct";
    case A::delete_all_curves:
      return "delete_all_curves";
    case A::write_curve:
      return "write_curve";
    case A::save_curves:
      return "save_curves";
    case A::start_mc:
      return "start_mc";
    case A::reset:
      return "reset";
    case A::delete_ct:
      return "delete_ct";
    case A::delete_curve:
      return "delete_curve";
  }
  return "?";
}

const char* write_reason_text(WriteReason r) {
  switch (r) {
    case WriteReason::differs:
      return "differs";
    case WriteReason::leftover:
      return "leftover back to its default";
    case WriteReason::again_after_defaulting:
      return "again after defaulting";
    case WriteReason::kept_communication:
      return "kept communication value";
  }
  return "?";
}

namespace {

nlohmann::ordered_json skipped_json(const SkippedValue& v) {
  nlohmann::ordered_json o;
  switch (v.kind) {
    case SkippedValue::Kind::parameter:
      o["layer"] = std::string(lmcfg::layers::name(v.layer));
      o["upid"] = hex(v.key, 4);
      break;
    case SkippedValue::Kind::curve:
      o["curve"] = v.key;
      break;
    case SkippedValue::Kind::ct_entry:
      o["ct_entry"] = v.key;
      break;
  }
  o["name"] = v.name;
  o["reason_code"] = reason_code(v.reason);
  o["reason"] = v.why;
  return o;
}

}  // namespace

std::string render_skipped_incompatible(const Plan& p) {
  if (p.skipped_incompatible.empty()) return {};
  std::string out = "skipped (the target cannot take them):\n";
  for (const auto& v : p.skipped_incompatible) out += "  " + v.text + "\n";
  return out;
}

std::string render_plan(const Plan& p) {
  std::string out;
  if (!p.ok()) {
    out +=
        "restore refused: " + std::to_string(p.problems.size()) + " problem(s), nothing written:\n";
    for (const auto& s : p.problems) out += "  problem: " + s + "\n";
    return out + render_skipped_incompatible(p);
  }
  if (p.nothing_to_do() && !p.skipped_incompatible.empty()) {
    out +=
        "plan: nothing to do: the target already matches the file except the skipped values "
        "(no write, MC keeps running)\n";
  } else if (p.nothing_to_do() && !p.kept.empty()) {
    out +=
        "plan: nothing to do: the target already matches the file except the values it keeps "
        "(no write, MC keeps running)\n";
  } else if (p.nothing_to_do()) {
    out +=
        "plan: nothing to do: the target already matches the file (no write, MC keeps running)\n";
  } else {
    out += "plan: " + std::to_string(p.steps.size()) + " step(s), about " +
           std::to_string(p.write_telegrams) + " write telegram(s)\n";
  }
  std::size_t n = 0;
  for (const auto& s : p.steps) out += "  " + std::to_string(++n) + ". " + s.text + "\n";
  for (const auto& s : p.losses) out += "  the target loses: " + s + "\n";
  for (const auto& s : p.skipped) out += "  skip: " + s + "\n";
  for (const auto& k : p.kept)
    out += "  stays different: " + kept_text(k, "file") + " (" + kept_reason(k.by) + ")\n";
  for (const auto& s : p.notes) out += "  note: " + s + "\n";
  out += render_skipped_incompatible(p);
  return out;
}

nlohmann::ordered_json plan_json(const Plan& p) {
  nlohmann::ordered_json j;
  j["problems"] = p.problems;
  j["nothing_to_do"] = p.nothing_to_do();
  nlohmann::ordered_json steps = nlohmann::ordered_json::array();
  std::size_t n = 0;
  for (const auto& s : p.steps) {
    nlohmann::ordered_json o;
    o["step"] = ++n;
    o["action"] = action_name(s.action);
    switch (s.action) {
      case PlanStep::Action::write_rom:
        o["layer"] = std::string(lmcfg::layers::name(s.layer));
        o["upid"] = hex(s.key, 4);
        o["name"] = s.name;
        if (s.old_value)
          o["old"] = {{"raw", *s.old_value}, {"display", s.old_display}};
        else
          o["old"] = nullptr;
        o["new"] = {{"raw", s.value}, {"display", s.new_display}};
        o["why"] = write_reason_text(s.reason);
        break;
      case PlanStep::Action::default_layer:
        o["layer"] = std::string(lmcfg::layers::name(s.layer));
        break;
      case PlanStep::Action::write_ct:
      case PlanStep::Action::delete_ct:
      case PlanStep::Action::write_curve:
      case PlanStep::Action::delete_curve:
        o["id"] = s.key;
        break;
      default:
        break;
    }
    o["text"] = s.text;
    steps.push_back(std::move(o));
  }
  j["steps"] = std::move(steps);
  j["losses"] = p.losses;
  j["skipped"] = p.skipped;
  nlohmann::ordered_json incompatible = nlohmann::ordered_json::array();
  for (const auto& v : p.skipped_incompatible) incompatible.push_back(skipped_json(v));
  j["skipped_incompatible"] = std::move(incompatible);
  j["notes"] = p.notes;
  nlohmann::ordered_json kept = nlohmann::ordered_json::array();
  for (const auto& k : p.kept) kept.push_back(kept_json(k, "file"));
  j["kept"] = std::move(kept);
  return j;
}

}  // namespace lmcfg::ops
