#include "ops/factory_reset.hpp"

#include "config/model.hpp"
#include "db/database.hpp"
#include "ops/restore.hpp"

namespace lmcfg::ops {

Result<DefaultReport> default_drive(client::Client& c, const DefaultOptions& opt,
                                    const db::Database* db) {
  DefaultReport rep;
  auto step = [&](const std::string& what, Result<void> r) -> Result<void> {
    if (!r.ok()) {
      Error e = std::move(r).error();
      e.message = what + ": " + e.message +
                  ". The drive may be partially defaulted (MC stopped); run the command again.";
      return e;
    }
    rep.done.push_back(what);
    if (opt.progress) opt.progress("default", rep.done.size(), 0);
    return {};
  };
  // The communication values to keep, read before anything changes.
  std::vector<client::ModifiedParam> keep;
  for (int layer = 1; layer <= 4; ++layer) {
    if (!opt.layers[static_cast<std::size_t>(layer - 1)]) continue;
    LMCFG_ASSIGN_OR_RETURN(auto mods, c.modified_list(layer));
    for (const auto& m : mods) {
      if (!is_comm_parameter(db, m.upid)) continue;
      if (opt.include_comm)
        rep.link_may_change = true;
      else
        keep.push_back(m);
    }
  }
  LMCFG_TRY(step("stop MC", c.stop_mc()));
  bool rom_changed = false;
  for (int layer = 1; layer <= 4; ++layer) {
    if (!opt.layers[static_cast<std::size_t>(layer - 1)]) continue;
    LMCFG_TRY(step(std::string("default ") + client::layer_name(layer) + " layer",
                   c.default_layer(layer)));
    rom_changed = true;
  }
  for (const auto& k : keep) {
    char what[64];
    std::snprintf(what, sizeof what, "keep communication parameter %04Xh = %u", k.upid, k.value);
    LMCFG_TRY(step(what, c.write_rom(k.upid, k.value)));
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
