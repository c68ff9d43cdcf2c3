#include "ops/factory_reset.hpp"

#include <map>

#include "common/layers.hpp"
#include "config/model.hpp"
#include "db/database.hpp"
#include "ops/recovery.hpp"
#include "ops/restore.hpp"

namespace lmcfg::ops {

Result<DefaultReport> default_drive(client::Client& c, const DefaultOptions& opt,
                                    const db::Database& db) {
  DefaultReport rep;
  bool record_saved = false, mc_stopped = false;
  const std::string record = opt.recovery_path.string();
  auto step = [&](const std::string& what, Result<void> r) -> Result<void> {
    if (!r.ok()) {
      Error e = std::move(r).error();
      const bool interrupted = e.code == make_error_code(Errc::interrupted);
      e.message = std::string(interrupted ? "interrupted at step '" : "stopped at step '") + what +
                  "': " + e.message +
                  (interrupted ? " (the telegram in flight was completed)" : "") +
                  ". The drive is partially defaulted" + (mc_stopped ? " (MC stopped)" : "") +
                  ": run the same command again" +
                  (record_saved ? "; it finishes from the recovery record " + record : "") +
                  (rep.undo ? "; the previous values are in the undo record " +
                                  rep.undo->path.string() + " (" + rep.undo->command + ")"
                            : std::string()) +
                  ".";
      return e;
    }
    rep.done.push_back(what);
    if (opt.progress) opt.progress("default", rep.done.size(), 0);
    return {};
  };
  // The communication values to keep, read before anything changes.
  std::map<std::uint16_t, std::uint32_t> keep;
  std::array<std::optional<std::vector<client::ModifiedParam>>, 4> seen;  // for the undo record
  for (int layer = 1; layer <= 4; ++layer) {
    if (!opt.layers[static_cast<std::size_t>(layer - 1)]) continue;
    LMCFG_ASSIGN_OR_RETURN(auto mods, c.modified_list(layer));
    seen[static_cast<std::size_t>(layer - 1)] = mods;
    for (const auto& m : mods) {
      if (!is_comm_parameter(db, m.upid)) continue;
      if (opt.include_comm)
        rep.link_may_change = true;
      else
        keep[m.upid] = m.value;
    }
  }
  if (opt.undo.enabled) {
    auto cfg = undo_config_for_default(c, seen, opt.curves, opt.command_table, db);
    if (!cfg.ok()) return std::move(cfg).error();  // reads only: nothing written
    LMCFG_ASSIGN_OR_RETURN(rep.undo, save_undo(opt.undo, *cfg, db));
  }
  // An earlier run stopped after defaulting: the drive no longer shows the
  // values it had; the record holds them.
  if (!opt.recovery_path.empty()) {
    LMCFG_ASSIGN_OR_RETURN(auto found, load_recovery(opt.recovery_path));
    if (found && !opt.include_comm) {
      for (const auto& k : found->keep) {
        const int layer = lmcfg::layers::of_upid(k.upid);
        if (layer != 0 && opt.layers[static_cast<std::size_t>(layer - 1)]) keep[k.upid] = k.value;
      }
      rep.recovered = true;
      rep.recovery_note = "found the recovery record " + record + " of an interrupted run (" +
                          found->created + "): writing back the values it recorded";
    }
    if (!keep.empty() && !found) {
      RecoveryRecord r{"default", opt.port, c.options().id, utc_now(), {}, {}};
      for (const auto& [upid, value] : keep) r.keep.push_back({upid, value});
      LMCFG_TRY(save_recovery(opt.recovery_path, r));
      rep.recovery_note = "recorded the values to keep in " + record;
    }
    record_saved = !keep.empty() || found.has_value();
  }
  LMCFG_TRY(step("stop MC", c.stop_mc()));
  mc_stopped = true;
  bool rom_changed = false;
  for (int layer = 1; layer <= 4; ++layer) {
    if (!opt.layers[static_cast<std::size_t>(layer - 1)]) continue;
    LMCFG_TRY(step("default " + std::string(lmcfg::layers::name(layer)) + " layer",
                   c.default_layer(layer)));
    rom_changed = true;
  }
  for (const auto& [upid, value] : keep) {
    char what[64];
    std::snprintf(what, sizeof what, "keep communication parameter %04Xh = %u", upid, value);
    LMCFG_TRY(step(what, c.write_rom_confirmed(upid, value)));
  }
  // Every kept value read back (§10 05h 01h) before the record goes.
  for (const auto& [upid, value] : keep) {
    char what[64];
    std::snprintf(what, sizeof what, "read back kept %04Xh", upid);
    auto back = c.read_rom(upid);
    if (back.ok() && *back != value) {
      back = Error(Errc::verify_mismatch, "the drive holds " + std::to_string(*back) +
                                              ", expected " + std::to_string(value));
    }
    LMCFG_TRY(step(what, back.ok() ? Result<void>() : Result<void>(std::move(back).error())));
    rep.kept.push_back({upid, value});
  }
  if (record_saved) {
    LMCFG_TRY(remove_recovery(opt.recovery_path));
    rep.recovery_note += rep.recovery_note.empty() ? "" : "; ";
    rep.recovery_note += "every kept value read back, record deleted";
  }
  if (opt.command_table) {
    LMCFG_TRY(step("delete all command table entries", c.delete_all_ct()));
    LMCFG_TRY(step("save command table to flash", c.save_ct()));
  }
  if (opt.curves) {
    LMCFG_TRY(step("delete all curves", c.delete_all_curves()));
    LMCFG_TRY(step("save curves to flash", c.save_curves()));
  }
  LMCFG_TRY(step("start MC", c.start_mc()));
  mc_stopped = false;
  if (rom_changed) {
    auto r = c.reset();
    // The drive answers after its restart (§13.1), already with its switch
    // settings; with the old link settings that answer can be lost.
    if (!r.ok() && rep.link_may_change && r.error().code == make_error_code(Errc::timeout)) {
      rep.done.push_back("reset (defaults become active; no answer with the old link settings)");
    } else {
      LMCFG_TRY(step("reset (defaults become active)", std::move(r)));
    }
  }
  return rep;
}

}  // namespace lmcfg::ops
