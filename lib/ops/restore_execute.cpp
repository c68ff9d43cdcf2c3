// Restore phase 2: execute the plan's steps in order. See restore.hpp.
#include <algorithm>

#include "common/layers.hpp"
#include "ops/long_step.hpp"
#include "ops/recovery.hpp"
#include "ops/restore.hpp"

namespace lmcfg::ops {

namespace {
// What a long step waits for, as Client::find_again and the notes name it
// ("" for a step that is not a long operation).
std::string long_step_what(const PlanStep& s) {
  using Action = PlanStep::Action;
  switch (s.action) {
    case Action::default_layer:
      return "defaulting layer " + std::string(lmcfg::layers::name(s.layer));
    case Action::save_ct:
      return "saving the command table to flash";
    case Action::save_curves:
      return "saving the curves to flash";
    case Action::start_mc:
      return "starting MC";
    case Action::reset:
      return "resetting the drive";
    default:
      return {};
  }
}

// The telegrams of one step.
Result<void> send_step(client::Client& c, const Plan& p, const PlanStep& s) {
  const config::DriveConfig& file = p.expected;
  using Action = PlanStep::Action;
  switch (s.action) {
    case Action::stop_mc:
      return c.stop_mc();
    case Action::default_layer:
      return c.default_layer(s.layer);
    case Action::write_rom:
      return c.write_rom_confirmed(static_cast<std::uint16_t>(s.key), s.value);
    case Action::delete_all_ct:
      return c.delete_all_ct();
    case Action::delete_ct:
      return c.delete_ct_entry(static_cast<std::uint16_t>(s.key));
    case Action::write_ct:
      return c.write_ct_entry(static_cast<std::uint16_t>(s.key), file.find_ct_entry(s.key)->raw);
    case Action::save_ct:
      return c.save_ct();
    case Action::delete_all_curves:
      return c.delete_all_curves();
    case Action::delete_curve:
      return c.delete_curve(static_cast<std::uint16_t>(s.key));
    case Action::write_curve: {
      const auto* cv = file.find_curve(s.key);
      return c.write_curve(static_cast<std::uint16_t>(s.key), cv->info, cv->data);
    }
    case Action::save_curves:
      return c.save_curves();
    case Action::start_mc:
      return c.start_mc();
    case Action::reset:
      // Restored link settings: the answer comes at them and is lost at the
      // old ones; the manual's wait, then run_restore looks for the drive
      // (link::reconnect_within) for as long as a slow one may need.
      if (p.link_may_change)
        return c.reset(std::min(c.options().reset_timeout, c.options().relink_reset_timeout));
      return c.reset();
  }
  return {};
}
}  // namespace

Result<void> execute_plan(client::Client& c, const Plan& p, const RestoreOptions& opt,
                          std::vector<std::string>* unacknowledged) {
  using Action = PlanStep::Action;
  if (!p.ok()) return Error(Errc::plan_refused, "the plan has problems; nothing written");
  std::size_t n = 0;
  bool mc_stopped = false;
  RecoveryRecord rec{"restore", opt.port, c.options().id, utc_now(), {}, {}, {}};
  if (!opt.recovery_path.empty()) {
    // Before the first destructive step: what a re-run must finish (§11/§12
    // flash saves it cannot see) and the communication values kept.
    for (const auto& s : p.steps)
      if (s.action == Action::write_rom && s.reason == WriteReason::kept_communication)
        rec.keep.push_back({static_cast<std::uint16_t>(s.key), s.value});
    LMCFG_TRY(save_recovery(opt.recovery_path, rec));
  }
  std::vector<std::string> unacked;
  for (const auto& s : p.steps) {
    ++n;
    if (opt.progress) opt.progress("restore", n, p.steps.size());
    Result<void> r = send_step(c, p, s);
    std::string long_what = long_step_what(s);
    // The drive answers a reset after its restart (§13.1), already with the
    // restored link settings; with the old ones that answer can be lost (the
    // caller finds it again with the new ones: link::reconnect).
    if (s.action == Action::reset && !r.ok() && p.link_may_change &&
        r.error().code == make_error_code(Errc::timeout)) {
      r = {};
      long_what.clear();
    }
    // A long step whose answer never came: find the drive again, go on, and
    // let the verify decide (ops/long_step.hpp; field reports, C1250 notes).
    bool long_timed_out = false;
    if (!long_what.empty() && !r.ok() && r.error().code == make_error_code(Errc::timeout)) {
      Error first = std::move(r).error();
      auto ls = long_step(c, long_what, [&]() -> Result<void> { return first; });
      if (ls.ok()) {
        unacked.push_back("step " + std::to_string(n) + " (" + s.text + "): " + ls->note);
        if (!opt.recovery_path.empty()) {
          rec.unacknowledged.push_back(s.text);  // a re-run saves the tables again
          LMCFG_TRY(save_recovery(opt.recovery_path, rec));
        }
        r = {};
      } else {
        r = std::move(ls).error();
        long_timed_out = r.error().code == make_error_code(Errc::timeout);
      }
    }
    if (!r.ok()) {
      Error e = std::move(r).error();
      const bool interrupted = e.code == make_error_code(Errc::interrupted);
      e.message = std::string(interrupted ? "restore interrupted" : "restore stopped") +
                  " at step " + std::to_string(n) + " of " + std::to_string(p.steps.size()) + " (" +
                  s.text + "): " + e.message +
                  (interrupted ? " (the telegram in flight was completed)" : "") +
                  ". The drive is partially configured" + (mc_stopped ? " and MC is stopped" : "");
      // A drive silent longer than both waits: running again with the same
      // waits would stop here again; say what is known instead.
      if (long_timed_out) {
        e.message += ": steps 1.." + std::to_string(n) + " were sent, steps 1.." +
                     std::to_string(n - 1) + " acknowledged" +
                     (unacked.empty() ? std::string()
                                      : " or answered after a missing acknowledgement (" +
                                            std::to_string(unacked.size()) + ")") +
                     ". Once the drive answers, run the same restore with longer waits to "
                     "converge.";
      } else {
        e.message += ": run the same restore again to converge.";
      }
      return e;
    }
    if (s.action == Action::stop_mc) mc_stopped = true;
    if (s.action == Action::start_mc || s.action == Action::reset) mc_stopped = false;
  }
  // Unacknowledged steps: the record stays until the verify has matched
  // (run_restore removes it), so a re-run after a mismatch saves the tables.
  if (!opt.recovery_path.empty() && unacked.empty()) LMCFG_TRY(remove_recovery(opt.recovery_path));
  if (unacknowledged) *unacknowledged = std::move(unacked);
  return {};
}

}  // namespace lmcfg::ops
