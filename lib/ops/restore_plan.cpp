// Restore phase 1: the plan (reads only). See restore.hpp.
#include <algorithm>
#include <map>
#include <set>

#include "common/bytes.hpp"
#include "common/layers.hpp"
#include "db/database.hpp"
#include "ops/compare.hpp"
#include "ops/expected_link.hpp"
#include "ops/recovery.hpp"
#include "ops/restore.hpp"
#include "ops/restore_internal.hpp"

namespace lmcfg::ops {

using namespace detail;

namespace {

using Action = PlanStep::Action;

bool is_comm(const db::Database& db, std::uint16_t upid) { return is_comm_parameter(db, upid); }

// Communication parameters last: a restore interrupted before them leaves the
// drive reachable with the settings it had. Among them, a value (2012h, 2076h)
// goes before its source select (200Eh, 206Ch) when the source ends "By
// Parameter", after it otherwise, so that a reset between the two writes
// (power loss) never activates a half-written pair.
void order_comm_writes_last(std::vector<PlanStep>& steps, std::size_t first,
                            const std::vector<config::Parameter>& final_values,
                            const db::Database& db) {
  auto final_of = [&](std::uint16_t upid) -> std::optional<std::uint32_t> {
    for (const auto& p : final_values)
      if (p.upid == upid) return p.value;
    return std::nullopt;
  };
  const bool baud_by_param = final_of(kBaudRateSource) == kBaudRateByParameter;
  const bool id_by_param = final_of(kMacidSource) == kMacidByParameter;
  auto rank = [&](const PlanStep& s) {
    if (s.action != PlanStep::Action::write_rom || !is_comm(db, static_cast<std::uint16_t>(s.key)))
      return 0;
    if (s.key == kBaudRateCode) return baud_by_param ? 1 : 3;
    if (s.key == kMacidValue) return id_by_param ? 1 : 3;
    return 2;
  };
  std::stable_sort(steps.begin() + static_cast<std::ptrdiff_t>(first), steps.end(),
                   [&](const PlanStep& a, const PlanStep& b) { return rank(a) < rank(b); });
}

// Defaulting a layer: LinRS §10.4 "could be more than 1 s"; 1.2 s as modelled
// by the simulator (docs/simulator.md). Only used to choose the cheaper way to
// bring leftovers to their defaults.
constexpr double kDefaultingEstimateUs = 1'200'000.0;

// One short exchange (9-byte request, 14-byte answer, ~1 ms turnaround, §6.1.1.1)
// at the link's byte time; 57600 8N1 when the link does not know it (TCP).
double telegram_estimate_us(client::Client& c) {
  double bt = c.link().byte_time_us();
  if (bt <= 0.0) bt = 10.0 * 1e6 / 57600.0;
  return 23.0 * bt + 1000.0;
}

// Phase 0: what the target says about an earlier run. MC stopped (status word
// and state var 0 in the default response, §6) means an earlier restore or
// default stopped half way: RAM tables may hold what flash does not, and ROM
// values may wait for their reset. A recovery record is left by a restore that
// did not finish. Either way the tables in scope are saved again and the drive
// reset, even where RAM matches.
struct EarlierRun {
  bool mc_was_stopped = false;
  std::optional<RecoveryRecord> rec;  // set: recovered from it
};

Result<EarlierRun> detect_earlier_run(client::Client& c, const RestoreOptions& opt, Plan& plan) {
  EarlierRun out;
  LMCFG_ASSIGN_OR_RETURN(auto state, c.default_response());
  out.mc_was_stopped = state.status_word.value_or(1) == 0 && state.state_var.value_or(1) == 0;
  if (!opt.recovery_path.empty()) {
    LMCFG_ASSIGN_OR_RETURN(out.rec, load_recovery(opt.recovery_path));
    if (out.rec) {
      plan.recovered_from = opt.recovery_path.string();
      plan.notes.push_back("found the recovery record " + opt.recovery_path.string() +
                           " of a restore that did not finish (" + out.rec->created +
                           "): the command table and curves in scope are saved to flash again "
                           "and the drive restarted");
      // ops/long_step.hpp: a save the drive never acknowledged is done again.
      for (const auto& u : out.rec->unacknowledged)
        plan.notes.push_back("the recovery record lists a step the drive never acknowledged: " + u);
    }
  }
  if (out.mc_was_stopped)
    plan.notes.push_back(
        "MC is stopped on the target (an earlier restore or default stopped half way?): the "
        "command table and curves are saved to flash again and the drive restarted");
  return out;
}

// One layer's parameters: the file's against the target's modified list.
struct LayerWork {
  int layer;
  std::vector<client::ModifiedParam> target;
  std::vector<Write> writes;                // differ from the target: checked, written
  std::vector<config::Parameter> same;      // listed on the target with the file's value
  std::vector<config::Parameter> keep;      // the target's communication values kept
  std::vector<config::Parameter> expected;  // what the layer holds afterwards
  std::vector<const client::ModifiedParam*> leftovers;  // into `target`
  std::map<std::uint16_t, std::uint32_t> on_target;     // `target` by UPID
  std::set<std::uint16_t> restored;                     // UPIDs the file restores
};

struct CompareProgress {
  std::size_t total = 0, checked = 0;
};

// The file's parameters of the layer that the restore writes: without the
// communication parameters unless --include-comm (those are listed as skipped).
std::vector<config::Parameter> restored_params(Builder& b, const config::DriveConfig& file,
                                               LayerWork& w) {
  std::vector<config::Parameter> out;
  for (const auto& p : file.layer(w.layer)) {
    if (kept_parameter(p.upid, b.db, b.opt.include_comm)) {
      b.plan.skipped.push_back(
          param_label(w.layer, p.upid, b.db.find(p.upid), &p) +
          ": communication parameter, the target keeps its own value (use --include-comm)");
      continue;
    }
    w.restored.insert(p.upid);
    w.expected.push_back(p);
    out.push_back(p);
  }
  return out;
}

// Phase 1a: compare first, what the target already holds is not written.
// Sorts the file's parameters of the layer into skipped (communication),
// same and writes; every restored one is expected afterwards.
Result<void> compare_parameters(Builder& b, const config::DriveConfig& file, LayerWork& w,
                                CompareProgress& progress) {
  const std::vector<config::Parameter> restored = restored_params(b, file, w);
  std::vector<config::Parameter> listed;
  for (const auto& m : w.target)
    listed.push_back(config::Parameter{m.upid, m.value, std::nullopt, std::nullopt, {}, {}, {}});
  // Not in the target's modified list: its ROM holds its default (§10.2). The
  // default rule shows a difference; where it does not, the file's value may
  // be the target's default: read it (05h 01h; a refusal: old value unknown,
  // the checks will say why).
  AskValue read_rom = [&](std::uint16_t upid) -> Result<std::optional<std::uint32_t>> {
    auto rom = b.c.read_rom(upid);
    if (rom.ok()) return std::optional<std::uint32_t>(*rom);
    if (!refused(rom.error())) return std::move(rom).error();
    return std::optional<std::uint32_t>();
  };
  const ParamSide target{&listed, config::ParamSet::modified, Resolve::rule_if_differs, read_rom};
  const ParamSide in_file{&restored, config::ParamSet::modified, Resolve::none, {}};
  auto visit = [&](std::uint16_t upid) {
    if (b.opt.progress && w.restored.count(upid))
      b.opt.progress("plan: comparing parameters", ++progress.checked, progress.total);
  };
  LMCFG_ASSIGN_OR_RETURN(const auto cmp,
                         ops::compare_parameters(w.layer, target, in_file, b.db, visit));
  for (const auto& row : cmp.rows) {
    if (!row.b.record) continue;  // the target's alone: sort_target_values
    const config::Parameter& p = *row.b.record;
    const bool listed_on_target = row.a.state == ParamValue::State::value;
    if (row.reason == Reason::same) {
      if (listed_on_target) w.same.push_back(p);
      continue;
    }
    const bool inferred =
        row.a.source == DefaultSource::database || row.a.source == DefaultSource::recorded;
    w.writes.push_back(Write{p, row.a.value, inferred ? " (default)" : "", WriteReason::differs});
  }
  return {};
}

// Phase 1b: the target's communication parameters survive the restore unless
// --include-comm; the rest of its modified list not in the file are leftovers.
void sort_target_values(const Builder& b, LayerWork& w) {
  for (const auto& m : w.target) {
    if (w.restored.count(m.upid)) continue;
    if (kept_parameter(m.upid, b.db, b.opt.include_comm)) {
      config::Parameter k{m.upid, m.value, std::nullopt, std::nullopt, {}, {}, {}};
      w.keep.push_back(k);
      w.expected.push_back(k);
      continue;
    }
    w.leftovers.push_back(&m);
  }
}

// Phase 1b': the values the restore keeps (ops/matching.hpp) where the file
// holds others, each side resolved by the default rule: the plan lists them,
// so that what stays different is said before the write.
Result<void> note_kept(Builder& b, const config::DriveConfig& file, const LayerWork& w) {
  std::vector<config::Parameter> in_file, on_target;
  for (const auto& p : file.layer(w.layer))
    if (kept_parameter(p.upid, b.db, b.opt.include_comm)) in_file.push_back(p);
  for (const auto& m : w.target)
    if (kept_parameter(m.upid, b.db, b.opt.include_comm))
      on_target.push_back(
          config::Parameter{m.upid, m.value, std::nullopt, std::nullopt, {}, {}, {}});
  if (in_file.empty() && on_target.empty()) return {};
  const ParamSide f{&in_file, config::ParamSet::modified, Resolve::rule_then_ask, {}};
  const ParamSide t{&on_target, config::ParamSet::modified, Resolve::rule_then_ask, {}};
  LMCFG_ASSIGN_OR_RETURN(const auto cmp, ops::compare_parameters(w.layer, f, t, b.db));
  for (const auto& row : cmp.rows) {
    if (row.reason == Reason::same) continue;
    // Both sides shown by the file's recorded type where the database has none (the sign).
    const std::optional<std::uint8_t> type = row.a.record ? row.a.record->type : std::nullopt;
    auto text = [&](const ParamValue& v) {
      return v.value ? display_value(b.db, row.upid, *v.value, type)
                     : std::string("its default (not known)");
    };
    DiffItem it;
    it.kind = DiffItem::Kind::parameter;
    it.layer = w.layer;
    it.key = row.upid;
    it.name = param_name(row.upid, b.db.find(row.upid), row.a.record ? row.a.record : row.b.record);
    it.a = text(row.a);
    it.b = text(row.b);
    b.plan.kept.push_back(KeptValue{std::move(it), *kept_parameter(row.upid, b.db, false)});
  }
  return {};
}

// Phase 1c: a layer defaulted by the unfinished run no longer lists the values
// it kept: the record has them (docs/restore.md).
void keep_recorded_values(const RecoveryRecord& rec, LayerWork& w) {
  for (const auto& k : rec.keep) {
    if (lmcfg::layers::of_upid(k.upid) != w.layer || w.restored.count(k.upid)) continue;
    config::Parameter kp{k.upid, k.value, std::nullopt, std::nullopt, {}, {}, {}};
    auto same = [&](const config::Parameter& x) { return x.upid == k.upid; };
    std::erase_if(w.keep, same);
    std::erase_if(w.expected, same);
    w.expected.push_back(kp);
    const auto listed = w.on_target.find(k.upid);
    if (listed != w.on_target.end() && listed->second == k.value)
      w.keep.push_back(kp);
    else
      w.writes.push_back(Write{kp, std::nullopt, "", WriteReason::kept_communication});
  }
}

// The target's address usage of each write the database does not know it of,
// one 05h/03h request each (LinRS 3V27 p27), instead of walking the layer's
// UPID list. nullopt when the target does not answer the request (the seed's
// generation: C3h/C4h): then the UPID list tells. A UPID the target does not
// know (C8h) is left out: the type query finds it absent.
Result<std::optional<std::map<std::uint16_t, std::uint16_t>>> ask_address_usage(
    Builder& b, const LayerWork& w) {
  std::map<std::uint16_t, std::uint16_t> usage;
  if (b.no_address_usage_request) return std::optional<std::map<std::uint16_t, std::uint16_t>>();
  for (const auto& x : w.writes) {
    const db::Parameter* d = b.db.find(x.p.upid);
    if (d && d->address_usage) continue;
    auto au = b.c.read_address_usage(x.p.upid);
    if (!au.ok()) {
      if (au.error().code == make_comm_state_error(0xC8)) continue;
      return std::move(au).error();
    }
    if (!*au) {
      b.no_address_usage_request = true;
      return std::optional<std::map<std::uint16_t, std::uint16_t>>();
    }
    usage[x.p.upid] = **au;
  }
  return std::optional<std::map<std::uint16_t, std::uint16_t>>(std::move(usage));
}

// Phase 1d: every write checked against the target. ROM write access must be
// known before a write (§10 address usage bit 3). Where the database does not
// know it, the target tells: per UPID where it answers 05h/03h (LinRS 3V27
// p27), else its UPID list, with the type of every UPID, in one walk of the
// layer. Returns the UPIDs the target cannot take.
Result<std::set<std::uint16_t>> check_writes(Builder& b, const LayerWork& w) {
  const int layer = w.layer;
  const std::size_t au_unknown = std::count_if(w.writes.begin(), w.writes.end(), [&](auto& x) {
    const db::Parameter* d = b.db.find(x.p.upid);
    return !(d && d->address_usage);
  });
  std::optional<std::map<std::uint16_t, client::UpidInfo>> listed;
  std::optional<std::map<std::uint16_t, std::uint16_t>> usage;
  const std::string lname(lmcfg::layers::name(layer));
  if (au_unknown) {
    LMCFG_ASSIGN_OR_RETURN(usage, ask_address_usage(b, w));
  }
  if (usage) {
    b.plan.notes.push_back(lname + ": the UPID database does not know the address usage of " +
                           std::to_string(au_unknown) +
                           " parameter(s); asked the target for each (05h/03h, LinRS 3V27 p27) "
                           "to check ROM write access");
  } else if (au_unknown) {
    const std::string phase = "plan: " + lname + " UPID list";
    LMCFG_ASSIGN_OR_RETURN(auto list, b.c.upid_list(layer, [&](std::size_t n) {
      if (b.opt.progress) b.opt.progress(phase, n, 0);
    }));
    listed.emplace();
    for (const auto& u : list) (*listed)[u.upid] = u;
    b.plan.notes.push_back(
        lname + ": the UPID database does not know the address usage of " +
        std::to_string(au_unknown) + " parameter(s); read the target's UPID list (" +
        std::to_string(list.size()) + " UPIDs, §10.3) to check ROM write access");
  }
  std::set<std::uint16_t> cannot;
  for (const auto& x : w.writes) {
    LMCFG_ASSIGN_OR_RETURN(
        const bool fits, check_parameter(b.c, b.db, b.opt, layer, x.p, listed ? &*listed : nullptr,
                                         usage ? &*usage : nullptr, b.plan));
    if (!fits) cannot.insert(x.p.upid);
  }
  return cannot;
}

// Phase 1d' (--skip-incompatible): a value the target cannot take is handled
// as if the file did not hold it: not written, not expected; the target's own
// value, if modified, is a leftover (a communication value is kept).
void drop_incompatible(const Builder& b, const std::set<std::uint16_t>& cannot, LayerWork& w) {
  auto dropped = [&](std::uint16_t upid) { return cannot.count(upid) > 0; };
  std::erase_if(w.writes, [&](const Write& x) { return dropped(x.p.upid); });
  std::erase_if(w.expected, [&](const config::Parameter& p) { return dropped(p.upid); });
  for (auto upid : cannot) w.restored.erase(upid);
  for (const auto& m : w.target) {
    if (!dropped(m.upid)) continue;
    if (is_comm(b.db, m.upid)) {
      config::Parameter k{m.upid, m.value, std::nullopt, std::nullopt, {}, {}, {}};
      w.keep.push_back(k);
      w.expected.push_back(k);
    } else {
      w.leftovers.push_back(&m);
    }
  }
}

// Phase 1e (--include-comm): compare the communication values the target uses
// now (modified list, or the default when not listed) with those the restore
// leaves.
void note_link_change(Builder& b, const LayerWork& w) {
  std::map<std::uint16_t, std::uint32_t> now, after;
  for (const auto& m : w.target)
    if (is_comm(b.db, m.upid)) now[m.upid] = m.value;
  for (const auto& p : w.expected)
    if (is_comm(b.db, p.upid)) after[p.upid] = p.value;
  for (const auto& x : w.same)
    if (is_comm(b.db, x.upid)) after[x.upid] = x.value;
  // The LinRS settings select the link only on a LinRS link (a LinUDP drive
  // is reached over UDP/IP whatever they hold, LinUDP V2 §3.2).
  if (b.c.capabilities().protocol != "LinRS") return;
  b.plan.link_may_change = b.plan.link_may_change || now != after;
}

// Phase 1: one layer in scope compared with the target and its writes checked.
Result<void> compare_layer(Builder& b, const config::DriveConfig& file, const EarlierRun& earlier,
                           CompareProgress& progress, LayerWork& w) {
  LMCFG_ASSIGN_OR_RETURN(w.target, b.c.modified_list(w.layer));
  b.plan.target.layers[static_cast<std::size_t>(w.layer - 1)] = w.target;
  for (const auto& m : w.target) w.on_target[m.upid] = m.value;
  LMCFG_TRY(compare_parameters(b, file, w, progress));
  sort_target_values(b, w);
  LMCFG_TRY(note_kept(b, file, w));
  if (earlier.rec && !b.opt.include_comm) keep_recorded_values(*earlier.rec, w);
  LMCFG_ASSIGN_OR_RETURN(const auto cannot, check_writes(b, w));
  if (b.opt.skip_incompatible && !cannot.empty()) drop_incompatible(b, cannot, w);
  if (b.opt.include_comm) note_link_change(b, w);
  std::sort(w.expected.begin(), w.expected.end(), [](auto& x, auto& y) { return x.upid < y.upid; });
  return {};
}

// A file's curves or command table in scope for a family without that group
// (B1100: "not on B1100", LinRS 3V27 §11-§12): a problem that refuses the
// restore, or with --skip-incompatible a table skipped. True: plan the
// tables (what is left of them in scope).
bool tables_exist(Builder& b, config::DriveConfig& file) {
  const families::Family* f = b.opt.family;
  if (!f) return true;
  const std::string name(f->name);
  auto missing = [&](bool& in_scope, bool has, const std::string& what, const char* section) {
    if (!in_scope || has) return;
    const std::string why = "a " + name + " has no " + what + " group (LinRS 3V27 " + section + ")";
    if (b.opt.skip_incompatible) {
      b.plan.skipped.push_back("the file's " + what + ": " + why);
      in_scope = false;
    } else {
      b.plan.problems.push_back("the file has a " + what + " in scope, but " + why +
                                "; --skip-incompatible restores the rest");
    }
  };
  missing(file.scope.curves, f->curves, "curve", "§11");
  missing(file.scope.command_table, f->command_table, "command table", "§12");
  if (b.plan.ok()) return true;
  b.plan.steps.clear();
  return false;
}

// Leftovers go back to their defaults either by defaulting the layer (§10.4,
// > 1 s; then what the target already held must be written again) or by
// writing each back to the default the target reports (05h 07h, a value the
// target accepts by definition). The cheaper one; same end state.
bool defaulting_is_cheaper(const RestoreOptions& opt, const LayerWork& w, double tel_us) {
  if (!opt.default_first || w.leftovers.empty()) return false;
  // DCF p8: a B1100 stores no defaults, so it has none to default a layer to.
  if (opt.family && !opt.family->stored_defaults) return false;
  const double cost_writes = 2.0 * static_cast<double>(w.leftovers.size()) * tel_us;
  const double cost_default =
      tel_us + kDefaultingEstimateUs + static_cast<double>(w.same.size() + w.keep.size()) * tel_us;
  return cost_default < cost_writes;
}

// Phase 2: the ROM steps of one layer, communication writes last. True when
// it added any.
Result<bool> schedule_layer(Builder& b, const LayerWork& w, double tel_us) {
  Plan& plan = b.plan;
  const std::size_t first_step = plan.steps.size();
  const std::string lname(lmcfg::layers::name(w.layer));
  plan.expected.layer(w.layer) = w.expected;
  if (defaulting_is_cheaper(b.opt, w, tel_us)) {
    PlanStep s;
    s.action = Action::default_layer;
    s.layer = w.layer;
    s.text = "default the " + lname + " layer's ROM values (§10.4); " +
             std::to_string(w.leftovers.size()) + " leftover(s) go back to their defaults";
    b.add(std::move(s), 1);
    for (const auto* m : w.leftovers)
      plan.notes.push_back("leftover " + lname + " " + hex(m->upid, 4, "h") + " = " +
                           display_value(b.db, m->upid, m->value, b.shown_type(m->upid, {})) +
                           " goes back to its default");
    for (const auto& x : w.writes) b.add_write(w.layer, x);
    for (const auto& p : w.same)
      b.add_write(w.layer, Write{p, std::nullopt, "", WriteReason::again_after_defaulting});
    for (const auto& p : w.keep)
      b.add_write(w.layer, Write{p, p.value, "", WriteReason::kept_communication});
  } else {
    for (const auto& x : w.writes) b.add_write(w.layer, x);
    for (const auto* m : w.leftovers) {
      auto def = b.c.get_default(m->upid);
      if (!def.ok()) {
        if (!refused(def.error())) return std::move(def).error();
        plan.problems.push_back(
            param_label(w.layer, m->upid, b.db.find(m->upid), nullptr) +
            ": leftover, but the target refused its default query: " + def.error().message);
        continue;
      }
      config::Parameter p{m->upid, *def, std::nullopt, std::nullopt, {}, {}, {}};
      b.add_write(w.layer, Write{p, m->value, "", WriteReason::leftover});
    }
  }
  order_comm_writes_last(plan.steps, first_step, w.expected, b.db);
  return plan.steps.size() > first_step;
}

// Phase 4: stop MC first; at the end the reset (ROM values act) or an MC start.
void add_stop_and_start(Builder& b, bool rom_changed) {
  PlanStep stop;
  stop.action = Action::stop_mc;
  stop.text =
      "stop MC and application software (§13.3): the axis stops until the end of the restore";
  b.plan.steps.insert(b.plan.steps.begin(), std::move(stop));
  b.plan.write_telegrams += 1;
  if (b.opt.reset_after && rom_changed) {
    // The reset restarts the firmware with MC running (§13.1), so a separate MC
    // start before it would only cost its ~3 s (§13.4).
    b.add(Action::reset, 0,
          "reset the drive so the ROM values become active; MC and application software start "
          "with it (§13.1)",
          1);
  } else {
    b.add(Action::start_mc, 0,
          std::string("start MC and application software (§13.4)") +
              (rom_changed ? "; the written ROM values act after the next restart" : ""),
          1);
  }
}

// Phase 5: where the reset leaves the drive. LinRS §15 MACID Source Select:
// "By Parameter: Take the value of MACID Parameter Value", and §9 "A Reset
// command or Power cycle restarts all SW instances": the reset puts the drive
// on the MACID its ROM selects, whatever it answers at now. A drive whose ROM
// selects another ID than the one the tool addresses (2076h written without a
// restart since) would leave that ID: the reset's answer (§13.1, "given after
// the reset is completed") comes from the new ID and is skipped, and on a line
// of several drives the new ID may be another drive's. Without --include-comm
// the restore keeps the link, so such a plan is refused before any write; with
// it, the tool follows the drive after the reset (link/relink.hpp).
void check_id_after_reset(Builder& b) {
  const bool resets = std::any_of(b.plan.steps.begin(), b.plan.steps.end(),
                                  [](const PlanStep& s) { return s.action == Action::reset; });
  if (!resets || b.plan.link_may_change || b.c.capabilities().protocol != "LinRS") return;
  const link::ExpectedLink after = expected_link(b.plan, b.db);
  const std::uint8_t now = b.c.options().id;
  if (!after.macid || *after.macid == now) return;
  if (b.opt.include_comm) {
    b.plan.link_may_change = true;
    return;
  }
  b.plan.problems.push_back(
      "the drive answers at MACID " + hex(now, 2, "h") + ", but its ROM selects MACID " +
      hex(*after.macid, 2, "h") + " (" + after.macid_reason +
      "): the restore's reset would move it to " + hex(*after.macid, 2, "h") +
      ", where another drive of the line may answer. Write the MACID " +
      "it keeps first ('lmcfg set " + hex(kMacidValue, 4, "h") + " " + std::to_string(now) +
      " --rom --include-comm'), or, on a line of its own, restore with --include-comm to "
      "follow it");
  b.plan.steps.clear();
}

}  // namespace

void detail::Builder::add_write(int layer, const Write& w) {
  const db::Parameter* d = db.find(w.p.upid);
  PlanStep s;
  s.action = Action::write_rom;
  s.layer = layer;
  s.key = w.p.upid;
  s.value = w.p.value;
  s.old_value = w.old;
  s.name = param_name(w.p.upid, d, &w.p);
  const std::optional<std::uint8_t> type = shown_type(w.p.upid, w.p.type);
  s.new_display = display_value(db, w.p.upid, w.p.value, type);
  s.old_display = w.old ? display_value(db, w.p.upid, *w.old, type) + w.old_note : std::string("?");
  s.reason = w.reason;
  s.text =
      "write ROM " + param_label(layer, w.p.upid, d, &w.p) + ": " + s.old_display + " -> " +
      s.new_display +
      (w.reason == WriteReason::differs ? std::string()
                                        : " (" + std::string(write_reason_text(w.reason)) + ")");
  add(std::move(s), 1);
}

Result<Plan> plan_restore(client::Client& c, const config::DriveConfig& file,
                          const db::Database& db, const RestoreOptions& opt) {
  Plan plan;
  plan.expected.identity = file.identity;
  plan.expected.scope = file.scope;
  // The tables the restore writes: the file's, less what the target cannot take.
  config::DriveConfig tables = check_tables(file, opt, plan);
  Builder b{c, db, opt, plan};
  if (!tables_exist(b, tables)) return plan;
  plan.expected.scope.curves = tables.scope.curves;
  plan.expected.scope.command_table = tables.scope.command_table;
  if (tables.scope.curves) plan.expected.curves = tables.curves;
  if (tables.scope.command_table) plan.expected.ct_entries = tables.ct_entries;
  LMCFG_ASSIGN_OR_RETURN(const EarlierRun earlier, detect_earlier_run(c, opt, plan));
  const bool recovered = earlier.rec.has_value();

  // Phase 1: compare and check every layer in scope; nothing is planned
  // while a problem stands.
  auto in_scope = [&](int layer) { return file.scope.layers[static_cast<std::size_t>(layer - 1)]; };
  CompareProgress progress;
  for (int layer = 1; layer <= 4; ++layer)
    if (in_scope(layer)) progress.total += file.layer(layer).size();
  std::vector<LayerWork> work;
  for (int layer = 1; layer <= 4; ++layer) {
    if (!in_scope(layer)) continue;
    LayerWork w{layer, {}, {}, {}, {}, {}, {}, {}, {}};
    LMCFG_TRY(compare_layer(b, file, earlier, progress, w));
    work.push_back(std::move(w));
  }
  if (!plan.ok()) return plan;

  // Phase 2: the ROM writes, layer by layer.
  const double tel_us = telegram_estimate_us(c);
  bool rom_changed = false;
  for (const auto& w : work) {
    LMCFG_ASSIGN_OR_RETURN(const bool changed, schedule_layer(b, w, tel_us));
    rom_changed = rom_changed || changed;
  }
  if (!plan.ok()) {
    plan.steps.clear();
    return plan;
  }

  // Phase 3: the tables, each saved to flash only when an entry of it is
  // written or deleted (a save takes up to 10 s and wears the flash). LinRS
  // cannot read flash (§11, §12), so RAM tables that match the file prove
  // nothing about flash after an earlier run stopped half way. Two signs make
  // the plan save the tables in scope even where RAM matches: MC stopped, or a
  // recovery record of an unfinished restore. Otherwise the reset (or MC
  // start) reloads RAM from flash and the verify after it finds a flash that
  // held another table: plan_table_pass writes and saves it then.
  // docs/restore.md.
  const bool force_save = earlier.mc_was_stopped || recovered;
  if (tables.scope.command_table) LMCFG_TRY(plan_command_table(b, tables, force_save));
  if (tables.scope.curves) LMCFG_TRY(plan_curves(b, tables, force_save));
  if (!plan.ok()) {  // a table the target has no group for (restore_tables.cpp)
    plan.steps.clear();
    return plan;
  }
  if (earlier.mc_was_stopped || recovered) rom_changed = true;  // restart so every ROM value acts
  if (plan.steps.empty() && !earlier.mc_was_stopped && !recovered)
    return plan;  // nothing to do: MC keeps running

  // Phase 4: MC stopped around the writes.
  add_stop_and_start(b, rom_changed);
  check_id_after_reset(b);
  return plan;
}

Result<Plan> plan_table_pass(client::Client& c, const Plan& done, const VerifyReport& v,
                             const RestoreOptions& opt) {
  Plan pass;
  pass.expected = done.expected;
  pass.skipped_incompatible = done.skipped_incompatible;
  Builder b{c, db::Database::empty(), opt, pass};  // the pass writes no parameter
  auto saved = [&](Action a) {
    return std::any_of(done.steps.begin(), done.steps.end(),
                       [&](const PlanStep& s) { return s.action == a; });
  };
  const config::DriveConfig& want = done.expected;
  if (v.ct_differs && want.scope.command_table && !saved(Action::save_ct))
    LMCFG_TRY(plan_command_table(b, want, false));
  if (v.curves_differ && want.scope.curves && !saved(Action::save_curves))
    LMCFG_TRY(plan_curves(b, want, false));
  if (pass.steps.empty()) return pass;
  add_stop_and_start(b, false);
  return pass;
}

}  // namespace lmcfg::ops
