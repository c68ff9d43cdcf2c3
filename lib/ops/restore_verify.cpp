// Restore phase 3: read the written scope back with backup's readers and list
// every mismatch the comparison (ops/compare.hpp) finds. See restore.hpp.
#include <algorithm>

#include "common/bytes.hpp"
#include "common/layers.hpp"
#include "db/database.hpp"
#include "ops/compare.hpp"
#include "ops/restore.hpp"

namespace lmcfg::ops {

namespace {

// One layer's modified list against the expected values. A value the drive
// does not list is read from its ROM (05h 01h): it holds its default there.
Result<void> verify_layer(client::Client& c, int layer, const config::DriveConfig& want,
                          VerifyReport& rep) {
  const std::string lname(lmcfg::layers::name(layer));
  LMCFG_ASSIGN_OR_RETURN(auto mods, c.modified_list(layer));
  std::vector<config::Parameter> on_drive;
  for (const auto& m : mods)
    on_drive.push_back(config::Parameter{m.upid, m.value, std::nullopt, std::nullopt, {}, {}, {}});
  AskValue read_rom = [&](std::uint16_t upid) -> Result<std::optional<std::uint32_t>> {
    LMCFG_ASSIGN_OR_RETURN(auto v, c.read_rom(upid));
    return std::optional<std::uint32_t>(v);
  };
  const ParamSide expected{&want.layer(layer), config::ParamSet::modified, Resolve::none, {}};
  const ParamSide drive{&on_drive, config::ParamSet::modified, Resolve::ask, read_rom};
  LMCFG_ASSIGN_OR_RETURN(const auto cmp,
                         compare_parameters(layer, expected, drive, db::Database::empty()));
  for (const auto& row : cmp.rows) {
    if (row.reason != Reason::differs) continue;
    rep.mismatches.push_back(lname + " " + hex(row.upid, 4, "h") + ": expected " +
                             std::to_string(*row.a.value) + ", drive has " +
                             std::to_string(*row.b.value));
  }
  for (const auto& row : cmp.rows) {
    if (row.reason != Reason::only_in_b) continue;
    rep.mismatches.push_back(lname + " " + hex(row.upid, 4, "h") + ": modified on the drive (" +
                             std::to_string(*row.b.value) + ") but not in the file");
  }
  return {};
}

}  // namespace

Result<VerifyReport> verify_restore(client::Client& c, const Plan& p, const RestoreOptions& opt) {
  VerifyReport rep;
  const config::DriveConfig& want = p.expected;
  for (int layer = 1; layer <= 4; ++layer) {
    if (want.scope.layers[static_cast<std::size_t>(layer - 1)])
      LMCFG_TRY(verify_layer(c, layer, want, rep));
  }
  if (want.scope.command_table) {
    std::vector<std::string> notes;  // an entry listed but empty: not there, as for backup
    LMCFG_ASSIGN_OR_RETURN(const auto on_drive,
                           read_command_table(c, Progress{}, "verify command table", notes));
    const auto rows = compare_ct_entries(want.ct_entries, on_drive);
    const bool ids_differ = std::any_of(rows.begin(), rows.end(),
                                        [](const CtRow& r) { return r.reason != Reason::differs; });
    if (ids_differ) {
      rep.mismatches.push_back("command table: drive defines " + std::to_string(on_drive.size()) +
                               " entries, the file " + std::to_string(want.ct_entries.size()));
    }
    for (const auto& row : rows)
      if (row.reason == Reason::differs)
        rep.mismatches.push_back("command table entry " + std::to_string(row.id) +
                                 ": bytes differ");
    rep.ct_differs = !rows.empty();
  }
  if (want.scope.curves) {
    LMCFG_ASSIGN_OR_RETURN(const auto on_drive,
                           read_curves(c, opt.max_curve_id, opt.progress, "verify curves"));
    const auto rows = compare_curves(want.curves, on_drive);
    for (const auto& row : rows) {
      const char* what = row.reason == Reason::only_in_a   ? ": missing on the drive"
                         : row.reason == Reason::only_in_b ? ": on the drive but not in the file"
                                                           : ": blocks differ";
      rep.mismatches.push_back("curve " + std::to_string(row.id) + what);
    }
    rep.curves_differ = !rows.empty();
  }
  return rep;
}

}  // namespace lmcfg::ops
