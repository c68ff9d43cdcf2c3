// Restore phase 1: the plan (reads only). See restore.hpp.
#include <algorithm>
#include <map>
#include <set>

#include "common/bytes.hpp"
#include "common/layers.hpp"
#include "db/database.hpp"
#include "ops/expected_link.hpp"
#include "ops/recovery.hpp"
#include "ops/restore.hpp"
#include "ops/restore_internal.hpp"

namespace lmcfg::ops {

using namespace detail;

const char* reason_code(Incompatibility r) {
  switch (r) {
    case Incompatibility::upid_absent:
      return "upid_absent";
    case Incompatibility::type_differs:
      return "type_differs";
    case Incompatibility::out_of_range:
      return "out_of_range";
    case Incompatibility::not_rom_writable:
      return "not_rom_writable";
    case Incompatibility::curve_id_limit:
      return "curve_id_limit";
    case Incompatibility::curve_memory:
      return "curve_memory";
    case Incompatibility::ct_entry_id:
      return "ct_entry_id";
    case Incompatibility::ct_entry_size:
      return "ct_entry_size";
  }
  return "?";
}

namespace {

using Action = PlanStep::Action;

bool is_comm(const db::Database& db, std::uint16_t upid) { return is_comm_parameter(db, upid); }

bool refused(const Error& e) { return e.code == ErrorClass::drive_refusal; }

std::string range_text(std::optional<std::int64_t> mn, std::optional<std::int64_t> mx) {
  return (mn ? std::to_string(*mn) : std::string("?")) + ".." +
         (mx ? std::to_string(*mx) : std::string("?"));
}

// A value of the file the target cannot take: a problem (its message as
// `text`), or with skip_incompatible a skipped value.
void incompatible(Plan& plan, const RestoreOptions& opt, SkippedValue v) {
  if (opt.skip_incompatible)
    plan.skipped_incompatible.push_back(std::move(v));
  else
    plan.problems.push_back(v.text);
}

SkippedValue skipped_value(SkippedValue::Kind kind, int layer, std::uint32_t key, std::string name,
                           std::string label, Incompatibility reason, std::string why) {
  SkippedValue v;
  v.kind = kind;
  v.layer = layer;
  v.key = key;
  v.name = std::move(name);
  v.reason = reason;
  v.text = std::move(label) + ": " + why;
  v.why = std::move(why);
  return v;
}

// Checks one parameter the restore will write against the target; appends
// problems or incompatible values (and notes where the database disagrees
// with the target). True when the target can take it. Link errors propagate.
// `listed`: the target's UPID list of the layer (§10.3), read when the
// database does not know every address usage; else the type is asked.
Result<bool> check_parameter(client::Client& c, const db::Database& db, const RestoreOptions& opt,
                             int layer, const config::Parameter& p,
                             const std::map<std::uint16_t, client::UpidInfo>* listed, Plan& plan) {
  const db::Parameter* d = db.find(p.upid);
  const std::string label = param_label(layer, p.upid, d, &p);
  auto cannot = [&](Incompatibility r, std::string why) {
    incompatible(plan, opt,
                 skipped_value(SkippedValue::Kind::parameter, layer, p.upid,
                               param_name(p.upid, d, &p), label, r, std::move(why)));
    return false;
  };
  std::uint16_t type = 0;
  std::optional<db::AddressUsage> address_usage;
  const char* au_source = "the UPID database's";
  if (d) address_usage = d->address_usage;
  if (listed) {
    auto it = listed->find(p.upid);
    if (it == listed->end()) {
      return cannot(Incompatibility::upid_absent, "UPID does not exist on the target (not in its " +
                                                      std::string(lmcfg::layers::name(layer)) +
                                                      " UPID list, §10.3)");
    }
    type = it->second.type;
    if (!address_usage) {
      address_usage = db::AddressUsage{it->second.address_usage};
      au_source = "the target's";
    }
  } else {
    auto asked = c.get_type(p.upid);
    if (!asked.ok()) {
      if (asked.error().code == make_comm_state_error(0xC8)) {
        return cannot(Incompatibility::upid_absent,
                      "UPID does not exist on the target (type query answered C8h unknown UPID)");
      }
      if (refused(asked.error())) {
        plan.problems.push_back(label +
                                ": the target refused the type query: " + asked.error().message);
        return false;
      }
      return std::move(asked).error();
    }
    type = *asked;
  }
  auto code = db::type_from_code(type);
  if (!code) {
    plan.problems.push_back(label + ": the target reports type code " + hex(type, 4, "h") +
                            ", which seed 003 §10 does not define");
    return false;
  }
  if (p.type && *p.type != type) {
    return cannot(Incompatibility::type_differs,
                  "type differs: the file has " +
                      std::string(db::type_name(static_cast<db::TypeCode>(*p.type))) +
                      ", the target has " + std::string(db::type_name(*code)));
  }
  if (d && d->spec.type && *d->spec.type != *code) {
    plan.notes.push_back(label + ": the target's type " + std::string(db::type_name(*code)) +
                         " differs from the UPID database's " +
                         std::string(db::type_name(*d->spec.type)) + "; the target's applies");
  }
  if (address_usage && !address_usage->rom_write()) {
    return cannot(Incompatibility::not_rom_writable,
                  "read-only on the target (" + std::string(au_source) + " address usage " +
                      hex(address_usage->raw, 4, "h") + " has no ROM write bit)");
  }
  auto value = db::field_integer(*code, p.value);
  if (!value) {
    return cannot(Incompatibility::out_of_range, "value " + hex(p.value, 4, "h") +
                                                     " does not fit type " +
                                                     std::string(db::type_name(*code)));
  }
  db::ValueSpec spec = d ? d->spec : db::ValueSpec{};
  spec.type = *code;
  if (!db::is_text_type(*code)) {
    // The target's range is the truth (docs/restore.md): the database describes
    // the firmware we know, the target may allow less (§10 05h 05h/06h).
    auto mn = c.get_min(p.upid);
    auto mx = mn.ok() ? c.get_max(p.upid) : Result<std::uint32_t>(mn.error());
    if (!mn.ok() || !mx.ok()) {
      Error e = !mn.ok() ? std::move(mn).error() : std::move(mx).error();
      if (!refused(e)) return e;
      plan.problems.push_back(label + ": the target refused the min/max query: " + e.message);
      return false;
    }
    const auto tmin = db::field_integer(*code, *mn), tmax = db::field_integer(*code, *mx);
    if (d && (d->spec.min || d->spec.max) && (d->spec.min != tmin || d->spec.max != tmax)) {
      plan.notes.push_back(label + ": the target's range " + range_text(tmin, tmax) +
                           " differs from the UPID database's " +
                           range_text(d->spec.min, d->spec.max) + "; the target's applies");
    }
    spec.min = tmin;
    spec.max = tmax;
  }
  if (auto r = db::check_range(spec, *value); !r.ok()) {
    return cannot(Incompatibility::out_of_range,
                  r.error().message + " (as the target reports it, §10 05h 05h/06h)");
  }
  return true;
}

// The file's curves and command table entries against the drive's limits.
// Returns what the restore writes: the file, less (with skip_incompatible) the
// curves and entries the target cannot take.
config::DriveConfig check_tables(const config::DriveConfig& file, const RestoreOptions& opt,
                                 Plan& plan) {
  config::DriveConfig kept = file;
  using Kind = SkippedValue::Kind;
  auto cannot = [&](Kind kind, std::uint32_t id, std::string name, Incompatibility r,
                    std::string why) {
    const std::string label =
        (kind == Kind::curve ? "curve " : "command table entry ") + std::to_string(id);
    incompatible(plan, opt, skipped_value(kind, 0, id, std::move(name), label, r, std::move(why)));
  };
  if (file.scope.curves) {
    if (file.curves.size() > opt.max_curve_id && !opt.skip_incompatible) {
      plan.problems.push_back("the file holds " + std::to_string(file.curves.size()) +
                              " curves; the drive stores at most " +
                              std::to_string(opt.max_curve_id));
    }
    std::set<std::uint32_t> skip;
    for (const auto& cv : file.curves) {
      const std::string label = "curve " + std::to_string(cv.id);
      if (cv.id < 1 || cv.id > opt.max_curve_id) {
        cannot(Kind::curve, cv.id, curve_name(cv.info), Incompatibility::curve_id_limit,
               "ID outside 1.." + std::to_string(opt.max_curve_id));
        skip.insert(cv.id);
      }
      if (auto r = config::check_curve_blocks(cv); !r.ok())
        plan.problems.push_back(label + ": " + r.error().message);
      if (cv.info.size() > 0xFFFF || cv.data.size() > 0xFFFF) {
        plan.problems.push_back(label +
                                ": a block exceeds the 16-bit size field of §11 (65535 bytes)");
      }
    }
    std::erase_if(kept.curves, [&](const config::Curve& cv) { return skip.count(cv.id) > 0; });
    auto memory_of = [](const std::vector<config::Curve>& curves) {
      std::size_t m = 0;
      for (const auto& cv : curves) m += cv.info.size() + cv.data.size();
      return m;
    };
    const std::size_t memory = memory_of(kept.curves);
    if (memory > opt.curve_memory && !opt.skip_incompatible) {
      plan.problems.push_back("curves need " + std::to_string(memory) +
                              " bytes of curve memory; the drive has " +
                              std::to_string(opt.curve_memory));
    } else if (memory > opt.curve_memory) {
      // Which curves to leave out is a choice: the highest IDs, until the rest fits.
      std::sort(kept.curves.begin(), kept.curves.end(),
                [](const config::Curve& x, const config::Curve& y) { return x.id < y.id; });
      while (!kept.curves.empty() && memory_of(kept.curves) > opt.curve_memory) {
        const config::Curve& last = kept.curves.back();
        cannot(Kind::curve, last.id, curve_name(last.info), Incompatibility::curve_memory,
               "the file's curves need " + std::to_string(memory) +
                   " bytes of curve memory, the drive has " + std::to_string(opt.curve_memory) +
                   "; left out from the highest ID down until the rest fits");
        kept.curves.pop_back();
      }
    }
  }
  if (file.scope.command_table) {
    std::set<std::uint32_t> skip;
    for (const auto& e : file.ct_entries) {
      if (e.id > config::kMaxCtEntryId) {
        cannot(Kind::ct_entry, e.id, config::ct_entry_name(e.raw), Incompatibility::ct_entry_id,
               "ID outside 0..255");
        skip.insert(e.id);
      }
      if (e.raw.size() != opt.ct_entry_size) {
        cannot(
            Kind::ct_entry, e.id, config::ct_entry_name(e.raw), Incompatibility::ct_entry_size,
            std::to_string(e.raw.size()) + " bytes, expected " + std::to_string(opt.ct_entry_size));
        skip.insert(e.id);
      }
    }
    std::erase_if(kept.ct_entries, [&](const config::CtEntry& e) { return skip.count(e.id) > 0; });
  }
  return kept;
}

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

std::size_t chunks(std::size_t n) { return (n + 3) / 4; }

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

// One parameter the plan writes, with the target's value before.
struct Write {
  config::Parameter p;
  std::optional<std::uint32_t> old;
  std::string old_note;  // "(its default)" when `old` was inferred, not read
  std::string why;
};

struct Builder {
  client::Client& c;
  const db::Database& db;
  const RestoreOptions& opt;
  Plan& plan;

  void add(PlanStep s, std::size_t telegrams) {
    plan.steps.push_back(std::move(s));
    plan.write_telegrams += telegrams;
  }
  void add(Action a, std::uint32_t key, std::string text, std::size_t telegrams) {
    PlanStep s;
    s.action = a;
    s.key = key;
    s.text = std::move(text);
    add(std::move(s), telegrams);
  }
  void add_write(int layer, const Write& w) {
    const db::Parameter* d = db.find(w.p.upid);
    PlanStep s;
    s.action = Action::write_rom;
    s.layer = layer;
    s.key = w.p.upid;
    s.value = w.p.value;
    s.old_value = w.old;
    s.name = param_name(w.p.upid, d, &w.p);
    s.new_display = display_value(db, w.p.upid, w.p.value, w.p.type);
    s.old_display =
        w.old ? display_value(db, w.p.upid, *w.old, w.p.type) + w.old_note : std::string("?");
    s.why = w.why;
    s.text = "write ROM " + param_label(layer, w.p.upid, d, &w.p) + ": " + s.old_display + " -> " +
             s.new_display + (w.why == "differs" ? std::string() : " (" + w.why + ")");
    add(std::move(s), 1);
  }
};

// The target's command table against the file's: entries that differ or are
// missing are written, entries only on the target deleted, one flash save when
// any is.
Result<void> plan_command_table(Builder& b, const config::DriveConfig& file, bool force_save) {
  LMCFG_ASSIGN_OR_RETURN(auto ids, b.c.ct_defined_entries());
  std::map<std::uint32_t, Bytes> target;
  std::size_t n = 0;
  for (auto id : ids) {
    if (b.opt.progress) b.opt.progress("plan: command table", ++n, ids.size());
    LMCFG_ASSIGN_OR_RETURN(target[id], b.c.read_ct_entry(id));
  }
  b.plan.target.ct_entries = target;
  std::vector<const config::CtEntry*> writes;
  std::vector<std::uint32_t> deletes;
  for (const auto& e : file.ct_entries) {
    auto it = target.find(e.id);
    if (it != target.end() && it->second == e.raw) continue;
    if (it != target.end()) {
      deletes.push_back(e.id);
      b.plan.losses.push_back("command table entry " + std::to_string(e.id) + " '" +
                              config::ct_entry_name(it->second) + "' replaced by the file's '" +
                              config::ct_entry_name(e.raw) + "'");
    }
    writes.push_back(&e);
  }
  for (const auto& [id, raw] : target) {
    if (file.find_ct_entry(id)) continue;
    deletes.push_back(id);
    b.plan.losses.push_back("command table entry " + std::to_string(id) + " '" +
                            config::ct_entry_name(raw) + "' deleted (not in the file)");
  }
  if (writes.empty() && deletes.empty() && !force_save) return {};
  std::sort(deletes.begin(), deletes.end());
  for (auto id : deletes) {
    b.add(Action::delete_ct, id,
          "delete command table entry " + std::to_string(id) + " '" +
              config::ct_entry_name(target[id]) + "' in RAM (§12 08h 02h)",
          1);
  }
  for (const auto* e : writes) {
    b.add(Action::write_ct, e->id,
          "write command table entry " + std::to_string(e->id) + " '" +
              config::ct_entry_name(e->raw) + "'",
          1 + chunks(e->raw.size()));
  }
  b.add(Action::save_ct, 0,
        "save the command table to flash (§12 08h 00h saves every entry; up to 10 s)", 1);
  return {};
}

// The target's curves against the file's (IDs 1..max_curve_id): a curve is
// compared by sizes, then info block, then data block, reading only as far as
// needed; its name comes from the info block. Curves that differ are deleted
// and written again, curves only on the target deleted, one flash save when
// any is (§11 has per-curve delete and add, but saving always covers every
// curve).
Result<void> plan_curves(Builder& b, const config::DriveConfig& file, bool force_save) {
  std::vector<const config::Curve*> writes;
  std::vector<std::pair<std::uint32_t, std::string>> deletes;
  auto& seen = b.plan.target.curves.emplace();
  for (std::uint16_t id = 1; id <= b.opt.max_curve_id; ++id) {
    if (b.opt.progress) b.opt.progress("plan: curves", id, b.opt.max_curve_id);
    LMCFG_ASSIGN_OR_RETURN(auto sizes, b.c.curve_sizes(id));
    const config::Curve* fc = file.find_curve(id);
    if (!sizes) {
      if (fc) writes.push_back(fc);
      continue;
    }
    Bytes info;
    if (sizes->info > 0) {
      LMCFG_ASSIGN_OR_RETURN(info, b.c.read_curve_info(id, sizes->info));
    }
    bool same = false;
    auto& s = seen.emplace_back(TargetSeen::CurveSeen{id, info, sizes->data, std::nullopt});
    if (fc && fc->info == info && fc->data.size() == sizes->data) {
      LMCFG_ASSIGN_OR_RETURN(auto data, b.c.read_curve_data(id, sizes->data));
      same = data == fc->data;
      s.data = std::move(data);
    }
    if (same) continue;
    const std::string name = curve_name(info);
    deletes.emplace_back(id, name);
    if (fc) {
      writes.push_back(fc);
      b.plan.losses.push_back("curve " + std::to_string(id) + " '" + name +
                              "' replaced by the file's '" + curve_name(fc->info) + "'");
    } else {
      b.plan.losses.push_back("curve " + std::to_string(id) + " '" + name +
                              "' deleted (not in the file)");
    }
  }
  if (writes.empty() && deletes.empty() && !force_save) return {};
  for (const auto& [id, name] : deletes)
    b.add(Action::delete_curve, id,
          "delete curve " + std::to_string(id) + " '" + name + "' in RAM (§11 04h 02h)", 1);
  for (const auto* cv : writes) {
    b.add(Action::write_curve, cv->id,
          "write curve " + std::to_string(cv->id) + " '" + curve_name(cv->info) + "'",
          1 + chunks(cv->info.size()) + chunks(cv->data.size()));
  }
  b.add(Action::save_curves, 0,
        "save curves to flash (§11 04h 00h saves every curve, there is no per-curve save; up to "
        "10 s)",
        1);
  return {};
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

// Phase 1a: compare first, what the target already holds is not written.
// Sorts the file's parameters of the layer into skipped (communication),
// same and writes; every restored one is expected afterwards.
Result<void> compare_parameters(Builder& b, const config::DriveConfig& file, LayerWork& w,
                                CompareProgress& progress) {
  const db::Database& db = b.db;
  const RestoreOptions& opt = b.opt;
  const int layer = w.layer;
  for (const auto& p : file.layer(layer)) {
    const db::Parameter* d = db.find(p.upid);
    if (is_comm(db, p.upid) && !opt.include_comm) {
      b.plan.skipped.push_back(
          param_label(layer, p.upid, d, &p) +
          ": communication parameter, the target keeps its own value (use --include-comm)");
      continue;
    }
    w.restored.insert(p.upid);
    w.expected.push_back(p);
    if (opt.progress)
      opt.progress("plan: comparing parameters", ++progress.checked, progress.total);
    if (auto it = w.on_target.find(p.upid); it != w.on_target.end()) {
      if (it->second == p.value)
        w.same.push_back(p);
      else
        w.writes.push_back(Write{p, it->second, "", "differs"});
      continue;
    }
    // Not in the target's modified list: its ROM holds its default (§10.2).
    std::optional<std::uint32_t> def;
    if (d && d->default_value)
      def = static_cast<std::uint32_t>(*d->default_value);
    else if (p.default_value)
      def = p.default_value;
    if (def && *def != p.value) {
      w.writes.push_back(Write{p, *def, " (default)", "differs"});
      continue;
    }
    // The file's value may be the target's default: read it (05h 01h).
    auto rom = b.c.read_rom(p.upid);
    if (!rom.ok()) {
      if (!refused(rom.error())) return std::move(rom).error();
      w.writes.push_back(Write{p, std::nullopt, "", "differs"});  // the checks will say why
      continue;
    }
    if (*rom != p.value) w.writes.push_back(Write{p, *rom, "", "differs"});
  }
  return {};
}

// Phase 1b: the target's communication parameters survive the restore unless
// --include-comm; the rest of its modified list not in the file are leftovers.
void sort_target_values(const Builder& b, LayerWork& w) {
  for (const auto& m : w.target) {
    if (w.restored.count(m.upid)) continue;
    if (is_comm(b.db, m.upid) && !b.opt.include_comm) {
      config::Parameter k{m.upid, m.value, std::nullopt, std::nullopt, {}, {}, {}};
      w.keep.push_back(k);
      w.expected.push_back(k);
      continue;
    }
    w.leftovers.push_back(&m);
  }
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
      w.writes.push_back(Write{kp, std::nullopt, "", "kept communication value"});
  }
}

// Phase 1d: every write checked against the target. ROM write access must be
// known before a write (§10 address usage bit 3). Where the database does not
// know it, the target's UPID list tells, with the type of every UPID, in one
// walk of the layer. Returns the UPIDs the target cannot take.
Result<std::set<std::uint16_t>> check_writes(Builder& b, const LayerWork& w) {
  const int layer = w.layer;
  const std::size_t au_unknown = std::count_if(w.writes.begin(), w.writes.end(), [&](auto& x) {
    const db::Parameter* d = b.db.find(x.p.upid);
    return !(d && d->address_usage);
  });
  std::optional<std::map<std::uint16_t, client::UpidInfo>> listed;
  if (au_unknown) {
    const std::string phase = "plan: " + std::string(lmcfg::layers::name(layer)) + " UPID list";
    LMCFG_ASSIGN_OR_RETURN(auto list, b.c.upid_list(layer, [&](std::size_t n) {
      if (b.opt.progress) b.opt.progress(phase, n, 0);
    }));
    listed.emplace();
    for (const auto& u : list) (*listed)[u.upid] = u;
    b.plan.notes.push_back(
        std::string(lmcfg::layers::name(layer)) +
        ": the UPID database does not know the address usage of " + std::to_string(au_unknown) +
        " parameter(s); read the target's UPID list (" + std::to_string(list.size()) +
        " UPIDs, §10.3) to check ROM write access");
  }
  std::set<std::uint16_t> cannot;
  for (const auto& x : w.writes) {
    LMCFG_ASSIGN_OR_RETURN(const bool fits, check_parameter(b.c, b.db, b.opt, layer, x.p,
                                                            listed ? &*listed : nullptr, b.plan));
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
  if (earlier.rec && !b.opt.include_comm) keep_recorded_values(*earlier.rec, w);
  LMCFG_ASSIGN_OR_RETURN(const auto cannot, check_writes(b, w));
  if (b.opt.skip_incompatible && !cannot.empty()) drop_incompatible(b, cannot, w);
  if (b.opt.include_comm) note_link_change(b, w);
  std::sort(w.expected.begin(), w.expected.end(), [](auto& x, auto& y) { return x.upid < y.upid; });
  return {};
}

// Leftovers go back to their defaults either by defaulting the layer (§10.4,
// > 1 s; then what the target already held must be written again) or by
// writing each back to the default the target reports (05h 07h, a value the
// target accepts by definition). The cheaper one; same end state.
bool defaulting_is_cheaper(const RestoreOptions& opt, const LayerWork& w, double tel_us) {
  if (!opt.default_first || w.leftovers.empty()) return false;
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
                           display_value(b.db, m->upid, m->value) + " goes back to its default");
    for (const auto& x : w.writes) b.add_write(w.layer, x);
    for (const auto& p : w.same)
      b.add_write(w.layer, Write{p, std::nullopt, "", "again after defaulting"});
    for (const auto& p : w.keep)
      b.add_write(w.layer, Write{p, p.value, "", "kept communication value"});
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
      b.add_write(w.layer, Write{p, m->value, "", "leftover back to its default"});
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
  if (!resets || b.plan.link_may_change) return;
  const link::ExpectedLink after = expected_link(b.plan, b.db);
  const std::uint8_t now = b.c.options().id;
  if (!after.macid || *after.macid == now) return;
  if (b.opt.include_comm) {
    b.plan.link_may_change = true;
    return;
  }
  std::string why;
  for (const auto& r : after.reasons)
    if (r.rfind("MACID ", 0) == 0) why = " (" + r + ")";
  b.plan.problems.push_back(
      "the drive answers at MACID " + hex(now, 2, "h") + ", but its ROM selects MACID " +
      hex(*after.macid, 2, "h") + why + ": the restore's reset would move it to " +
      hex(*after.macid, 2, "h") + ", where another drive of the line may answer. Write the MACID " +
      "it keeps first ('lmcfg set " + hex(kMacidValue, 4, "h") + " " + std::to_string(now) +
      " --rom --include-comm'), or, on a line of its own, restore with --include-comm to "
      "follow it");
  b.plan.steps.clear();
}

}  // namespace

Result<Plan> plan_restore(client::Client& c, const config::DriveConfig& file,
                          const db::Database& db, const RestoreOptions& opt) {
  Plan plan;
  plan.expected.identity = file.identity;
  plan.expected.scope = file.scope;
  // The tables the restore writes: the file's, less what the target cannot take.
  const config::DriveConfig tables = check_tables(file, opt, plan);
  if (file.scope.curves) plan.expected.curves = tables.curves;
  if (file.scope.command_table) plan.expected.ct_entries = tables.ct_entries;
  Builder b{c, db, opt, plan};
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
  if (file.scope.command_table) LMCFG_TRY(plan_command_table(b, tables, force_save));
  if (file.scope.curves) LMCFG_TRY(plan_curves(b, tables, force_save));
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
