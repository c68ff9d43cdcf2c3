// Restore phase 3: read the target back and list every mismatch. See restore.hpp.
#include <map>

#include "common/bytes.hpp"
#include "common/layers.hpp"
#include "ops/restore.hpp"
#include "ops/restore_internal.hpp"

namespace lmcfg::ops {

Result<VerifyReport> verify_restore(client::Client& c, const Plan& p, const RestoreOptions& opt) {
  VerifyReport rep;
  const config::DriveConfig& want = p.expected;
  for (int layer = 1; layer <= 4; ++layer) {
    if (!want.scope.layers[static_cast<std::size_t>(layer - 1)]) continue;
    const std::string lname(lmcfg::layers::name(layer));
    LMCFG_ASSIGN_OR_RETURN(auto mods, c.modified_list(layer));
    std::map<std::uint16_t, std::uint32_t> on_drive;
    for (const auto& m : mods) on_drive[m.upid] = m.value;
    for (const auto& e : want.layer(layer)) {
      auto it = on_drive.find(e.upid);
      std::uint32_t actual;
      if (it != on_drive.end()) {
        actual = it->second;
        on_drive.erase(it);
      } else {
        // Not in the modified list: its ROM holds the default. Read it to compare.
        LMCFG_ASSIGN_OR_RETURN(actual, c.read_rom(e.upid));
      }
      if (actual != e.value) {
        rep.mismatches.push_back(lname + " " + hex(e.upid, 4, "h") + ": expected " +
                                 std::to_string(e.value) + ", drive has " + std::to_string(actual));
      }
    }
    for (const auto& [upid, value] : on_drive) {
      rep.mismatches.push_back(lname + " " + hex(upid, 4, "h") + ": modified on the drive (" +
                               std::to_string(value) + ") but not in the file");
    }
  }
  if (want.scope.command_table) {
    LMCFG_ASSIGN_OR_RETURN(auto ids, c.ct_defined_entries());
    std::vector<std::uint16_t> expected_ids;
    for (const auto& e : want.ct_entries) expected_ids.push_back(static_cast<std::uint16_t>(e.id));
    const std::size_t before = rep.mismatches.size();
    if (ids != expected_ids) {
      rep.mismatches.push_back("command table: drive defines " + std::to_string(ids.size()) +
                               " entries, the file " + std::to_string(expected_ids.size()));
    }
    for (auto id : ids) {
      const auto* e = want.find_ct_entry(id);
      if (!e) continue;
      LMCFG_ASSIGN_OR_RETURN(auto raw, c.read_ct_entry(id));
      if (raw != e->raw)
        rep.mismatches.push_back("command table entry " + std::to_string(id) + ": bytes differ");
    }
    rep.ct_differs = rep.mismatches.size() > before;
  }
  if (want.scope.curves) {
    const std::size_t before = rep.mismatches.size();
    for (std::uint16_t id = 1; id <= opt.max_curve_id; ++id) {
      if (opt.progress) opt.progress("verify curves", id, opt.max_curve_id);
      auto read = c.read_curve(id);
      if (!read.ok()) return std::move(read).error();
      const auto& blocks = read.value();
      const auto* cv = want.find_curve(id);
      if (!blocks && !cv) continue;
      if (!blocks) {
        rep.mismatches.push_back("curve " + std::to_string(id) + ": missing on the drive");
      } else if (!cv) {
        rep.mismatches.push_back("curve " + std::to_string(id) +
                                 ": on the drive but not in the file");
      } else if (blocks->info != cv->info || blocks->data != cv->data) {
        rep.mismatches.push_back("curve " + std::to_string(id) + ": blocks differ");
      }
    }
    rep.curves_differ = rep.mismatches.size() > before;
  }
  return rep;
}

}  // namespace lmcfg::ops
