// Restore phase 2: execute the plan's steps in order. See restore.hpp.
#include "ops/recovery.hpp"
#include "ops/restore.hpp"

namespace lmcfg::ops {

Result<void> execute_plan(client::Client& c, const Plan& p, const RestoreOptions& opt) {
  using Action = PlanStep::Action;
  if (!p.ok()) return Error(Errc::plan_refused, "the plan has problems; nothing written");
  const config::DriveConfig& file = p.expected;
  std::size_t n = 0;
  bool mc_stopped = false;
  if (!opt.recovery_path.empty()) {
    // Before the first destructive step: what a re-run must finish (§11/§12
    // flash saves it cannot see) and the communication values kept.
    RecoveryRecord rec{"restore", opt.port, c.options().id, utc_now(), {}, {}};
    for (const auto& s : p.steps)
      if (s.action == Action::write_rom && s.reason == WriteReason::kept_communication)
        rec.keep.push_back({static_cast<std::uint16_t>(s.key), s.value});
    LMCFG_TRY(save_recovery(opt.recovery_path, rec));
  }
  for (const auto& s : p.steps) {
    ++n;
    if (opt.progress) opt.progress("restore", n, p.steps.size());
    Result<void> r;
    switch (s.action) {
      case Action::stop_mc:
        r = c.stop_mc();
        break;
      case Action::default_layer:
        r = c.default_layer(s.layer);
        break;
      case Action::write_rom:
        r = c.write_rom_confirmed(static_cast<std::uint16_t>(s.key), s.value);
        break;
      case Action::delete_all_ct:
        r = c.delete_all_ct();
        break;
      case Action::delete_ct:
        r = c.delete_ct_entry(static_cast<std::uint16_t>(s.key));
        break;
      case Action::write_ct:
        r = c.write_ct_entry(static_cast<std::uint16_t>(s.key), file.find_ct_entry(s.key)->raw);
        break;
      case Action::save_ct:
        r = c.save_ct();
        break;
      case Action::delete_all_curves:
        r = c.delete_all_curves();
        break;
      case Action::delete_curve:
        r = c.delete_curve(static_cast<std::uint16_t>(s.key));
        break;
      case Action::write_curve: {
        const auto* cv = file.find_curve(s.key);
        r = c.write_curve(static_cast<std::uint16_t>(s.key), cv->info, cv->data);
        break;
      }
      case Action::save_curves:
        r = c.save_curves();
        break;
      case Action::start_mc:
        r = c.start_mc();
        break;
      case Action::reset:
        r = c.reset();
        // The drive answers after its restart (§13.1), already with the restored
        // link settings; with the old ones that answer can be lost.
        if (!r.ok() && p.link_may_change && r.error().code == make_error_code(Errc::timeout))
          r = {};
        break;
    }
    if (!r.ok()) {
      Error e = std::move(r).error();
      const bool interrupted = e.code == make_error_code(Errc::interrupted);
      e.message = std::string(interrupted ? "restore interrupted" : "restore stopped") +
                  " at step " + std::to_string(n) + " of " + std::to_string(p.steps.size()) + " (" +
                  s.text + "): " + e.message +
                  (interrupted ? " (the telegram in flight was completed)" : "") +
                  ". The drive is partially configured" + (mc_stopped ? " and MC is stopped" : "") +
                  ": run the same restore again to converge.";
      return e;
    }
    if (s.action == Action::stop_mc) mc_stopped = true;
    if (s.action == Action::start_mc || s.action == Action::reset) mc_stopped = false;
  }
  if (!opt.recovery_path.empty()) LMCFG_TRY(remove_recovery(opt.recovery_path));
  return {};
}

}  // namespace lmcfg::ops
