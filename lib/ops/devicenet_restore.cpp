// The DeviceNet restore run and its plan as JSON. See devicenet_restore.hpp.
#include "ops/devicenet_restore.hpp"

#include "common/bytes.hpp"

namespace lmcfg::ops {
namespace {

bool cancelled(const DevicenetRestoreRunOptions& o) { return o.cancel && o.cancel->load(); }

Error interrupted() { return Error(Errc::interrupted, "interrupted: the connection was released"); }

std::string motor_name(int motor) {
  return motor == config::kDevicenetController ? std::string("controller")
                                               : std::string(1, static_cast<char>('A' + motor));
}

}  // namespace

RestoreOutcome run_devicenet_restore(DevicenetSession& session, const config::DriveConfig& file,
                                     const db::Database& db, const DevicenetRestoreRunOptions& o) {
  using S = RestoreOutcome::Stage;
  RestoreOutcome out;
  auto fail = [&](Error e) {
    out.stage = S::failed;
    out.error = std::move(e);
    return std::move(out);
  };
  auto& m = session.master();
  std::vector<std::string> notes;
  DevicenetBackupOptions read = o.read;
  read.live = false;
  read.notes = &notes;
  read.progress = o.progress;
  auto current = devicenet_backup(m, read, db);
  if (!current.ok()) {
    out.devicenet.emplace().notes = std::move(notes);
    return fail(std::move(current).error());
  }
  if (cancelled(o)) {
    out.devicenet.emplace().notes = std::move(notes);
    return fail(interrupted());
  }
  out.devicenet = plan_devicenet_restore(file, *current, db);
  auto& plan = *out.devicenet;
  plan.notes = std::move(notes);
  out.set_commands = plan.writes.size();
  if (plan.refused()) {
    out.stage = S::plan_refused;
    return out;
  }
  if (o.dry_run) {
    out.stage = S::dry_run;
    return out;
  }
  // The plan compared every value of the file with the controller.
  if (plan.writes.empty()) {
    out.stage = S::nothing_to_do;
    return out;
  }
  if (o.confirm) {
    auto consent = o.confirm(plan);
    if (!consent.ok()) return fail(std::move(consent).error());
    if (*consent == Consent::declined) {
      out.stage = S::declined;
      return out;
    }
  }
  if (cancelled(o)) return fail(interrupted());
  out.written = true;
  auto mismatches = execute_devicenet_plan(m, plan, file, db, o.progress);
  if (!mismatches.ok()) return fail(std::move(mismatches).error());
  out.mismatches = std::move(mismatches).value();
  out.stage = out.mismatches.empty() ? S::restored : S::verify_mismatch;
  return out;
}

nlohmann::ordered_json devicenet_plan_json(const DevicenetPlan& p) {
  nlohmann::ordered_json j;
  j["problems"] = p.problems;
  j["nothing_to_do"] = !p.refused() && p.writes.empty();
  nlohmann::ordered_json steps = nlohmann::ordered_json::array();
  for (const auto& w : p.writes) {
    steps.push_back({{"step", steps.size() + 1},
                     {"action", "devicenet_set"},
                     {"motor", motor_name(w.motor)},
                     {"command", hex(w.get + 1u, 2, "h")},
                     {"name", w.name},
                     {"old", {{"raw", w.from}, {"display", w.from_display}}},
                     {"new", {{"raw", w.to}, {"display", w.to_display}}},
                     {"text", w.what}});
  }
  j["steps"] = std::move(steps);
  j["losses"] = nlohmann::ordered_json::array();
  j["skipped"] = nlohmann::ordered_json::array();
  j["skipped_incompatible"] = nlohmann::ordered_json::array();
  nlohmann::ordered_json notes = p.notes;
  notes.push_back(kRuntimeNote);
  j["notes"] = std::move(notes);
  j["devicenet"] = {{"unchanged", p.unchanged}};
  return j;
}

}  // namespace lmcfg::ops
