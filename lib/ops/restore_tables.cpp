// Restore phase 1, the tables: the target's command table entries and curves
// read, compared with the file's (ops/compare.hpp) and scheduled. See
// restore.hpp.
#include <algorithm>
#include <map>

#include "ops/backup.hpp"
#include "ops/compare.hpp"
#include "ops/restore.hpp"
#include "ops/restore_internal.hpp"

namespace lmcfg::ops::detail {

using Action = PlanStep::Action;

// Entries that differ or are missing are written, entries only on the target
// deleted, one flash save when any is.
namespace {
// LinRS 3V27 p32: on a C1100 curve and command table add/delete act on flash
// directly and "save to flash" has no function: no save step, and a delete is
// no RAM-only change.
bool direct_flash(const Builder& b) { return b.opt.family && !b.opt.family->flash_save; }
const char* where(const Builder& b) { return direct_flash(b) ? "on flash (C1100)" : "in RAM"; }

// The target answered the group's first request with C3h: it has no such
// group (ops::no_such_group; LinRS §16.1 "C3h Undefined Message Main ID", a
// B1100 per LinRS 3V27 §11-§12). Nothing to write when the file holds none of
// it; a file that holds some is refused, or with --skip-incompatible the table
// is skipped. Either way the group leaves the expected scope (no verify).
void target_lacks_group(Builder& b, bool curves, std::size_t in_file) {
  const std::string what = curves ? "curve" : "command table";
  const std::string why = "the target has no " + what +
                          " group (it answers C3h undefined message main ID, LinRS §16.1)";
  config::DriveConfig& want = b.plan.expected;
  (curves ? want.scope.curves : want.scope.command_table) = false;
  want.scope.drive_lacks.push_back(curves ? "curves" : "command_table");
  if (curves) {
    want.curves.clear();
    b.plan.target.curves.reset();
  } else {
    want.ct_entries.clear();
  }
  const std::string held =
      std::to_string(in_file) + " " +
      (curves ? "curve(s)" : "command table entr" + std::string(in_file == 1 ? "y" : "ies"));
  if (in_file == 0) {
    b.plan.notes.push_back(why + "; the file holds no " + (curves ? "curves" : "entries") +
                           ": nothing to write there");
  } else if (b.opt.skip_incompatible) {
    b.plan.skipped.push_back("the file's " + held + ": " + why);
  } else {
    b.plan.problems.push_back("the file holds " + held + ", but " + why +
                              "; --skip-incompatible restores the rest");
  }
}
}  // namespace

Result<void> plan_command_table(Builder& b, const config::DriveConfig& file, bool force_save) {
  auto listed = b.c.ct_defined_entries();  // the group's first request
  if (!listed.ok() && no_such_group(listed.error())) {
    target_lacks_group(b, false, file.ct_entries.size());
    return {};
  }
  LMCFG_ASSIGN_OR_RETURN(auto ids, std::move(listed));
  std::map<std::uint32_t, Bytes> target;
  std::vector<config::CtEntry> on_target;
  std::size_t n = 0;
  for (auto id : ids) {
    if (b.opt.progress) b.opt.progress("plan: command table", ++n, ids.size());
    LMCFG_ASSIGN_OR_RETURN(target[id], b.c.read_ct_entry(id));
    on_target.push_back(config::CtEntry{id, target[id]});
  }
  b.plan.target.ct_entries = target;
  const std::vector<CtRow> rows = compare_ct_entries(on_target, file.ct_entries);
  std::vector<const config::CtEntry*> writes;
  std::vector<std::uint32_t> deletes;
  for (const auto& row : rows) {  // the file's entries first, then the target's alone
    if (!row.b) continue;
    if (row.a) {
      deletes.push_back(row.id);
      b.plan.losses.push_back("command table entry " + std::to_string(row.id) + " '" +
                              config::ct_entry_name(row.a->raw) + "' replaced by the file's '" +
                              config::ct_entry_name(row.b->raw) + "'");
    }
    writes.push_back(row.b);
  }
  for (const auto& row : rows) {
    if (row.reason != Reason::only_in_a) continue;
    deletes.push_back(row.id);
    b.plan.losses.push_back("command table entry " + std::to_string(row.id) + " '" +
                            config::ct_entry_name(row.a->raw) + "' deleted (not in the file)");
  }
  if (writes.empty() && deletes.empty() && !force_save) return {};
  std::sort(deletes.begin(), deletes.end());
  for (auto id : deletes) {
    b.add(Action::delete_ct, id,
          "delete command table entry " + std::to_string(id) + " '" +
              config::ct_entry_name(target[id]) + "' " + where(b) + " (§12 08h 02h)",
          1);
  }
  for (const auto* e : writes) {
    b.add(Action::write_ct, e->id,
          "write command table entry " + std::to_string(e->id) + " '" +
              config::ct_entry_name(e->raw) + "'",
          1 + chunks(e->raw.size()));
  }
  if (direct_flash(b)) return {};
  b.add(Action::save_ct, 0,
        "save the command table to flash (§12 08h 00h saves every entry; up to 10 s)", 1);
  return {};
}

namespace {

// The target's curves (IDs 1..max_curve_id), read only as far as the
// comparison with the file needs: sizes, then the info block, then the data
// block where sizes and info match the file's curve. Where the data is not
// read the curve differs by its info or size anyway; it stands in as zeros of
// its size, which differ from the file's data of another size.
Result<std::vector<config::Curve>> read_target_curves(Builder& b, const config::DriveConfig& file) {
  std::vector<config::Curve> out;
  auto& seen = b.plan.target.curves.emplace();
  for (std::uint16_t id = 1; id <= b.opt.max_curve_id; ++id) {
    if (b.opt.progress) b.opt.progress("plan: curves", id, b.opt.max_curve_id);
    LMCFG_ASSIGN_OR_RETURN(auto sizes, b.c.curve_sizes(id));
    if (!sizes) continue;
    Bytes info;
    if (sizes->info > 0) {
      LMCFG_ASSIGN_OR_RETURN(info, b.c.read_curve_info(id, sizes->info));
    }
    auto& s = seen.emplace_back(TargetSeen::CurveSeen{id, info, sizes->data, std::nullopt});
    const config::Curve* fc = file.find_curve(id);
    if (fc && fc->info == info && fc->data.size() == sizes->data) {
      LMCFG_ASSIGN_OR_RETURN(auto data, b.c.read_curve_data(id, sizes->data));
      s.data = data;
      out.push_back(config::Curve{id, std::move(info), std::move(data)});
    } else {
      out.push_back(config::Curve{id, std::move(info), Bytes(sizes->data, 0)});
    }
  }
  return out;
}

}  // namespace

// A curve that differs is deleted and written again, a curve only on the
// target deleted, one flash save when any is (§11 has per-curve delete and
// add, but saving always covers every curve). Names come from info blocks.
Result<void> plan_curves(Builder& b, const config::DriveConfig& file, bool force_save) {
  auto read = read_target_curves(b, file);
  if (!read.ok() && no_such_group(read.error()) && b.plan.target.curves &&
      b.plan.target.curves->empty()) {  // C3h to the first probe
    target_lacks_group(b, true, file.curves.size());
    return {};
  }
  LMCFG_ASSIGN_OR_RETURN(const auto on_target, std::move(read));
  std::vector<const config::Curve*> writes;
  std::vector<std::pair<std::uint32_t, std::string>> deletes;
  for (const auto& row : compare_curves(on_target, file.curves)) {
    if (row.b) writes.push_back(row.b);
    if (!row.a) continue;
    const std::string name = curve_name(row.a->info);
    deletes.emplace_back(row.id, name);
    if (row.b) {
      b.plan.losses.push_back("curve " + std::to_string(row.id) + " '" + name +
                              "' replaced by the file's '" + curve_name(row.b->info) + "'");
    } else {
      b.plan.losses.push_back("curve " + std::to_string(row.id) + " '" + name +
                              "' deleted (not in the file)");
    }
  }
  if (writes.empty() && deletes.empty() && !force_save) return {};
  if (!deletes.empty() && !b.c.capabilities().delete_one_curve) {
    // LinUDP has no single-curve delete (LinUDP V2 p13-p15; LinRS §11 has one): every
    // curve is deleted and the file's curves are all written again.
    b.add(Action::delete_all_curves, 0,
          std::string("delete all curves ") + where(b) + " (" + b.c.capabilities().protocol +
              " cannot delete one curve)",
          1);
    deletes.clear();
    writes.clear();
    for (const auto& cv : file.curves) writes.push_back(&cv);
  }
  for (const auto& [id, name] : deletes)
    b.add(Action::delete_curve, id,
          "delete curve " + std::to_string(id) + " '" + name + "' " + where(b) + " (§11 04h 02h)",
          1);
  for (const auto* cv : writes) {
    b.add(Action::write_curve, cv->id,
          "write curve " + std::to_string(cv->id) + " '" + curve_name(cv->info) + "'",
          1 + chunks(cv->info.size()) + chunks(cv->data.size()));
  }
  if (direct_flash(b)) return {};
  b.add(Action::save_curves, 0,
        "save curves to flash (§11 04h 00h saves every curve, there is no per-curve save; up to "
        "10 s)",
        1);
  return {};
}

}  // namespace lmcfg::ops::detail
