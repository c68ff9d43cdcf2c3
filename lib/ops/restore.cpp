#include "ops/restore.hpp"

#include <algorithm>
#include <map>
#include <set>

#include "db/database.hpp"

namespace lmcfg::ops {

bool is_comm_parameter(const db::Database* db, std::uint16_t upid) {
  if (upid == kBaudRateSource || upid == kBaudRateCode || upid == kMacidSource ||
      upid == kMacidValue)
    return true;
  const db::Parameter* d = db ? db->find(upid) : nullptr;
  return d && d->comm;
}

namespace {

using Action = PlanStep::Action;

std::string hex4(std::uint32_t v) {
  char buf[12];
  std::snprintf(buf, sizeof buf, "%04Xh", v);
  return buf;
}

std::string param_label(int layer, std::uint16_t upid, const db::Parameter* d,
                        const config::Parameter* p) {
  std::string s = std::string(config::layer_name(layer)) + " " + hex4(upid);
  const std::string& name = d && !d->name.empty() ? d->name : (p ? p->name : std::string());
  if (!name.empty()) s += " " + name;
  return s;
}

// The 4-byte field as an integer of its type: upper bytes must be zero, or
// the sign extension for signed types (a drive may send either for SINT8/16).
std::optional<std::int64_t> as_integer(db::TypeCode t, std::uint32_t raw) {
  const unsigned bits = 8 * db::type_size(t);
  if (db::is_text_type(t) || t == db::TypeCode::LinFloat) return static_cast<std::int64_t>(raw);
  if (t == db::TypeCode::Bool || t == db::TypeCode::RadioDirBit)
    return raw <= 1 ? std::optional<std::int64_t>(raw) : std::nullopt;
  if (bits >= 32) {
    return db::is_signed_type(t) ? static_cast<std::int64_t>(static_cast<std::int32_t>(raw))
                                 : static_cast<std::int64_t>(raw);
  }
  const std::uint32_t mask = (1u << bits) - 1;
  const std::uint32_t upper = raw & ~mask;
  if (upper == 0) {
    if (!db::is_signed_type(t)) return static_cast<std::int64_t>(raw);
    const std::uint32_t sign = 1u << (bits - 1);
    return (raw & sign) ? static_cast<std::int64_t>(raw) - (static_cast<std::int64_t>(1) << bits)
                        : static_cast<std::int64_t>(raw);
  }
  if (db::is_signed_type(t) && upper == ~mask && (raw & (1u << (bits - 1)))) {
    return static_cast<std::int64_t>(static_cast<std::int32_t>(raw));
  }
  return std::nullopt;
}

bool is_comm(const db::Database* db, std::uint16_t upid) { return is_comm_parameter(db, upid); }

// Checks one parameter against the target; appends problems. Link errors
// propagate. `listed`: the target's UPID list of the layer (§10.3), read when
// the database does not know every address usage; else the type is asked.
Result<void> check_parameter(client::Client& c, const db::Database* db, int layer,
                             const config::Parameter& p,
                             const std::map<std::uint16_t, client::UpidInfo>* listed, Plan& plan) {
  const db::Parameter* d = db ? db->find(p.upid) : nullptr;
  const std::string label = param_label(layer, p.upid, d, &p);
  std::uint16_t type = 0;
  std::optional<db::AddressUsage> address_usage;
  const char* au_source = "the UPID database's";
  if (d) address_usage = d->address_usage;
  if (listed) {
    auto it = listed->find(p.upid);
    if (it == listed->end()) {
      plan.problems.push_back(label + ": UPID does not exist on the target (not in its " +
                              std::string(config::layer_name(layer)) + " UPID list, §10.3)");
      return {};
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
        plan.problems.push_back(
            label + ": UPID does not exist on the target (type query answered C8h unknown UPID)");
        return {};
      }
      if (asked.error().code.category() == comm_state_category()) {
        plan.problems.push_back(label +
                                ": the target refused the type query: " + asked.error().message);
        return {};
      }
      return std::move(asked).error();
    }
    type = *asked;
  }
  auto code = db::type_from_code(type);
  if (!code) {
    plan.problems.push_back(label + ": the target reports type code " + hex4(type) +
                            ", which seed 003 §10 does not define");
    return {};
  }
  if (p.type && *p.type != type) {
    plan.problems.push_back(label + ": type differs: the file has " +
                            std::string(db::type_name(static_cast<db::TypeCode>(*p.type))) +
                            ", the target has " + std::string(db::type_name(*code)));
    return {};
  }
  if (address_usage && !address_usage->rom_write()) {
    plan.problems.push_back(label + ": read-only on the target (" + au_source + " address usage " +
                            hex4(address_usage->raw) + " has no ROM write bit)");
    return {};
  }
  auto value = as_integer(*code, p.value);
  if (!value) {
    plan.problems.push_back(label + ": value " + hex4(p.value) + " does not fit type " +
                            std::string(db::type_name(*code)));
    return {};
  }
  db::ValueSpec spec = d ? d->spec : db::ValueSpec{};
  spec.type = *code;
  if (!db::is_text_type(*code) && (!spec.min || !spec.max)) {
    // The database does not know the range: ask the drive (§10 05h/06h).
    LMCFG_ASSIGN_OR_RETURN(auto mn, c.get_min(p.upid));
    LMCFG_ASSIGN_OR_RETURN(auto mx, c.get_max(p.upid));
    spec.min = as_integer(*code, mn);
    spec.max = as_integer(*code, mx);
  }
  if (auto r = db::check_range(spec, *value); !r.ok()) {
    plan.problems.push_back(label + ": " + r.error().message);
  }
  return {};
}

void check_tables(const config::DriveConfig& file, const RestoreOptions& opt, Plan& plan) {
  std::size_t memory = 0;
  if (file.scope.curves) {
    if (file.curves.size() > opt.max_curve_id) {
      plan.problems.push_back("the file holds " + std::to_string(file.curves.size()) +
                              " curves; the drive stores at most " +
                              std::to_string(opt.max_curve_id));
    }
    for (const auto& cv : file.curves) {
      const std::string label = "curve " + std::to_string(cv.id);
      if (cv.id < 1 || cv.id > opt.max_curve_id) {
        plan.problems.push_back(label + ": ID outside 1.." + std::to_string(opt.max_curve_id));
      }
      if (auto r = config::check_curve_blocks(cv); !r.ok())
        plan.problems.push_back(label + ": " + r.error().message);
      if (cv.info.size() > 0xFFFF || cv.data.size() > 0xFFFF) {
        plan.problems.push_back(label +
                                ": a block exceeds the 16-bit size field of §11 (65535 bytes)");
      }
      memory += cv.info.size() + cv.data.size();
    }
    if (memory > opt.curve_memory) {
      plan.problems.push_back("curves need " + std::to_string(memory) +
                              " bytes of curve memory; the drive has " +
                              std::to_string(opt.curve_memory));
    }
  }
  if (file.scope.command_table) {
    for (const auto& e : file.ct_entries) {
      const std::string label = "command table entry " + std::to_string(e.id);
      if (e.id > config::kMaxCtEntryId) plan.problems.push_back(label + ": ID outside 0..255");
      if (e.raw.size() != opt.ct_entry_size) {
        plan.problems.push_back(label + ": " + std::to_string(e.raw.size()) + " bytes, expected " +
                                std::to_string(opt.ct_entry_size));
      }
    }
  }
}

// Communication parameters last: a restore interrupted before them leaves the
// drive reachable with the settings it had. Among them, a value (2012h, 2076h)
// goes before its source select (200Eh, 206Ch) when the source ends "By
// Parameter", after it otherwise, so that a reset between the two writes
// (power loss) never activates a half-written pair.
void order_comm_writes_last(std::vector<PlanStep>& steps, std::size_t first,
                            const std::vector<config::Parameter>& final_values,
                            const db::Database* db) {
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

void add_step(Plan& p, Action a, int layer, std::uint32_t key, std::uint32_t value,
              std::string text, std::size_t write_telegrams) {
  p.steps.push_back(PlanStep{a, layer, key, value, std::move(text)});
  p.write_telegrams += write_telegrams;
}

std::size_t chunks(std::size_t n) { return (n + 3) / 4; }

// Defaulting a layer: seed 003 §10.4 "could be more than 1 s"; 1.2 s as modelled
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

}  // namespace

Result<Plan> plan_restore(client::Client& c, const config::DriveConfig& file,
                          const db::Database* db, const RestoreOptions& opt) {
  Plan plan;
  plan.expected.identity = file.identity;
  plan.expected.scope = file.scope;
  if (file.scope.curves) plan.expected.curves = file.curves;
  if (file.scope.command_table) plan.expected.ct_entries = file.ct_entries;
  check_tables(file, opt, plan);

  struct LayerWork {
    int layer;
    std::vector<client::ModifiedParam> target;
    std::vector<config::Parameter> writes;
  };
  std::vector<LayerWork> work;
  std::size_t checked = 0, total = 0;
  for (const auto& l : file.layers) total += l.size();
  for (int layer = 1; layer <= 4; ++layer) {
    if (!file.scope.layers[static_cast<std::size_t>(layer - 1)]) continue;
    LayerWork w{layer, {}, {}};
    LMCFG_ASSIGN_OR_RETURN(w.target, c.modified_list(layer));
    std::vector<const config::Parameter*> to_check;
    for (const auto& p : file.layer(layer)) {
      if (is_comm(db, p.upid) && !opt.include_comm) {
        plan.skipped.push_back(
            param_label(layer, p.upid, db ? db->find(p.upid) : nullptr, &p) +
            ": communication parameter, the target keeps its own value (use --include-comm)");
        continue;
      }
      to_check.push_back(&p);
    }
    // ROM write access must be known before a write (§10 address usage bit 3).
    // Where the database does not know it, the target's UPID list tells, with
    // the type of every UPID, in one walk of the layer.
    const std::size_t au_unknown =
        std::count_if(to_check.begin(), to_check.end(), [&](const config::Parameter* p) {
          const db::Parameter* d = db ? db->find(p->upid) : nullptr;
          return !(d && d->address_usage);
        });
    std::optional<std::map<std::uint16_t, client::UpidInfo>> listed;
    if (au_unknown) {
      const std::string phase = "plan: " + std::string(config::layer_name(layer)) + " UPID list";
      LMCFG_ASSIGN_OR_RETURN(auto list, c.upid_list(layer, [&](std::size_t n) {
        if (opt.progress) opt.progress(phase, n, 0);
      }));
      listed.emplace();
      for (const auto& u : list) (*listed)[u.upid] = u;
      plan.notes.push_back(
          std::string(config::layer_name(layer)) +
          ": the UPID database does not know the address usage of " + std::to_string(au_unknown) +
          " parameter(s); read the target's UPID list (" + std::to_string(list.size()) +
          " UPIDs, §10.3) to check ROM write access");
    }
    for (const auto* p : to_check) {
      if (opt.progress) opt.progress("plan: checking parameters", ++checked, total);
      LMCFG_TRY(check_parameter(c, db, layer, *p, listed ? &*listed : nullptr, plan));
      w.writes.push_back(*p);
    }
    // The target's communication parameters survive the restore unless --include-comm.
    for (const auto& m : w.target) {
      if (!is_comm(db, m.upid)) continue;
      const bool file_has =
          std::any_of(file.layer(layer).begin(), file.layer(layer).end(),
                      [&](const config::Parameter& p) { return p.upid == m.upid; });
      if (!opt.include_comm || !file_has) {
        if (opt.include_comm) continue;  // the file's (default) value wins
        w.writes.push_back(
            config::Parameter{m.upid, m.value, std::nullopt, std::nullopt, {}, {}, {}});
        plan.notes.push_back(param_label(layer, m.upid, db ? db->find(m.upid) : nullptr, nullptr) +
                             ": target's communication value " + hex4(m.value) + " kept");
      }
    }
    if (opt.include_comm) {
      // Compare the communication values the target uses now (modified list, or
      // the default when not listed) with those the restore leaves.
      std::map<std::uint16_t, std::uint32_t> now, after;
      for (const auto& m : w.target)
        if (is_comm(db, m.upid)) now[m.upid] = m.value;
      for (const auto& p : w.writes)
        if (is_comm(db, p.upid)) after[p.upid] = p.value;
      plan.link_may_change = plan.link_may_change || now != after;
    }
    std::sort(w.writes.begin(), w.writes.end(), [](auto& a, auto& b) { return a.upid < b.upid; });
    work.push_back(std::move(w));
  }
  if (!plan.ok()) return plan;

  add_step(plan, Action::stop_mc, 0, 0, 0, "stop MC and application software (§13.3)", 1);
  const double tel_us = telegram_estimate_us(c);
  bool rom_changed = false;
  for (auto& w : work) {
    const std::size_t first_step = plan.steps.size();
    const std::string lname(config::layer_name(w.layer));
    auto& expected = plan.expected.layer(w.layer);
    std::map<std::uint16_t, std::uint32_t> on_target;
    for (const auto& m : w.target) on_target[m.upid] = m.value;
    std::set<std::uint16_t> wanted;
    for (const auto& p : w.writes) wanted.insert(p.upid);
    // Leftovers: modified on the target, not written by the restore.
    std::vector<const client::ModifiedParam*> leftovers;
    for (const auto& m : w.target)
      if (!wanted.count(m.upid)) leftovers.push_back(&m);
    // Writes that the target's modified list already shows with the file's value.
    std::size_t already = 0;
    for (const auto& p : w.writes) {
      auto it = on_target.find(p.upid);
      already += (it != on_target.end() && it->second == p.value) ? 1 : 0;
    }
    // default_first brings the layer to its defaults before writing. The modified
    // list names every ROM value that differs from its default (§10.2), so the
    // defaulting command (> 1 s, §10.4) is only needed when leftovers exist, and
    // writing the few leftovers back to their defaults reaches the same ROM state
    // in less wire time. Pick whichever costs less; the end state is identical.
    bool use_defaulting = false;
    if (opt.default_first && !leftovers.empty()) {
      std::size_t leftover_telegrams = 0;
      for (const auto* m : leftovers) {
        const db::Parameter* d = db ? db->find(m->upid) : nullptr;
        leftover_telegrams +=
            (d && d->default_value) ? 1 : 2;  // default query when the database lacks it
      }
      const double cost_writes = static_cast<double>(leftover_telegrams) * tel_us;
      const double cost_default =
          tel_us + kDefaultingEstimateUs + static_cast<double>(already) * tel_us;
      use_defaulting = cost_default < cost_writes;
    }
    if (use_defaulting) {
      add_step(plan, Action::default_layer, w.layer, 0, 0,
               "default the " + lname + " layer's ROM values (§10.4)", 1);
      rom_changed = true;
      for (const auto* m : leftovers)
        plan.notes.push_back("leftover " + lname + " " + hex4(m->upid) + " = " + hex4(m->value) +
                             " goes back to its default");
      for (const auto& p : w.writes) {
        add_step(plan, Action::write_rom, w.layer, p.upid, p.value,
                 "write ROM " + param_label(w.layer, p.upid, db ? db->find(p.upid) : nullptr, &p) +
                     " = " + display_value(db, p.upid, p.value, p.type),
                 1);
      }
    } else {
      for (const auto& p : w.writes) {
        auto it = on_target.find(p.upid);
        if (it != on_target.end() && it->second == p.value) continue;  // already there
        add_step(plan, Action::write_rom, w.layer, p.upid, p.value,
                 "write ROM " + param_label(w.layer, p.upid, db ? db->find(p.upid) : nullptr, &p) +
                     " = " + display_value(db, p.upid, p.value, p.type),
                 1);
        rom_changed = true;
      }
      for (const auto* m : leftovers) {
        const db::Parameter* d = db ? db->find(m->upid) : nullptr;
        std::uint32_t def = 0;
        if (d && d->default_value) {
          def = static_cast<std::uint32_t>(*d->default_value);
        } else {
          LMCFG_ASSIGN_OR_RETURN(def, c.get_default(m->upid));
        }
        if (opt.default_first)
          plan.notes.push_back("leftover " + lname + " " + hex4(m->upid) + " = " + hex4(m->value) +
                               " goes back to its default");
        add_step(plan, Action::write_rom, w.layer, m->upid, def,
                 "set leftover " + param_label(w.layer, m->upid, d, nullptr) +
                     " back to its default " + std::to_string(def),
                 1);
        rom_changed = true;
      }
    }
    order_comm_writes_last(plan.steps, first_step, w.writes, db);
    expected = w.writes;
  }
  if (file.scope.command_table) {
    add_step(plan, Action::delete_all_ct, 0, 0, 0, "delete all command table entries in RAM (§12)",
             1);
    for (const auto& e : file.ct_entries) {
      add_step(plan, Action::write_ct, 0, e.id, 0,
               "write command table entry " + std::to_string(e.id) + " '" +
                   config::ct_entry_name(e.raw) + "'",
               1 + chunks(e.raw.size()));
    }
    add_step(plan, Action::save_ct, 0, 0, 0, "save the command table to flash (§12, up to 10 s)",
             1);
  }
  if (file.scope.curves) {
    add_step(plan, Action::delete_all_curves, 0, 0, 0, "delete all curves in RAM (§11)", 1);
    for (const auto& cv : file.curves) {
      auto v = config::decode_curve(cv);
      add_step(
          plan, Action::write_curve, 0, cv.id, 0,
          "write curve " + std::to_string(cv.id) + (v.ok() ? " '" + v->name + "'" : std::string()),
          1 + chunks(cv.info.size()) + chunks(cv.data.size()));
    }
    add_step(plan, Action::save_curves, 0, 0, 0, "save curves to flash (§11, up to 10 s)", 1);
  }
  if (opt.reset_after && rom_changed) {
    // The reset restarts the firmware with MC running (§13.1), so a separate MC
    // start before it would only cost its ~3 s (§13.4).
    add_step(plan, Action::reset, 0, 0, 0,
             "reset the drive so the ROM values become active; MC and application software start "
             "with it (§13.1)",
             1);
  } else {
    add_step(plan, Action::start_mc, 0, 0, 0, "start MC and application software (§13.4)", 1);
  }
  return plan;
}

std::string render_plan(const Plan& p) {
  std::string out;
  if (!p.ok()) {
    out +=
        "restore refused: " + std::to_string(p.problems.size()) + " problem(s), nothing written:\n";
    for (const auto& s : p.problems) out += "  problem: " + s + "\n";
    return out;
  }
  out += "plan: " + std::to_string(p.steps.size()) + " step(s), about " +
         std::to_string(p.write_telegrams) + " write telegram(s)\n";
  std::size_t n = 0;
  for (const auto& s : p.steps) out += "  " + std::to_string(++n) + ". " + s.text + "\n";
  for (const auto& s : p.skipped) out += "  skip: " + s + "\n";
  for (const auto& s : p.notes) out += "  note: " + s + "\n";
  return out;
}

Result<void> execute_plan(client::Client& c, const Plan& p, const RestoreOptions& opt) {
  if (!p.ok()) return Error(Errc::plan_refused, "the plan has problems; nothing written");
  const config::DriveConfig& file = p.expected;
  std::size_t n = 0;
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
      case Action::write_ct:
        r = c.write_ct_entry(static_cast<std::uint16_t>(s.key), file.find_ct_entry(s.key)->raw);
        break;
      case Action::save_ct:
        r = c.save_ct();
        break;
      case Action::delete_all_curves:
        r = c.delete_all_curves();
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
      e.message = "restore stopped at step " + std::to_string(n) + " of " +
                  std::to_string(p.steps.size()) + " (" + s.text + "): " + e.message +
                  ". The drive is partially configured; run the same restore again to converge.";
      return e;
    }
  }
  return {};
}

Result<VerifyReport> verify_restore(client::Client& c, const Plan& p, const RestoreOptions& opt) {
  VerifyReport rep;
  const config::DriveConfig& want = p.expected;
  for (int layer = 1; layer <= 4; ++layer) {
    if (!want.scope.layers[static_cast<std::size_t>(layer - 1)]) continue;
    const std::string lname(config::layer_name(layer));
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
        rep.mismatches.push_back(lname + " " + hex4(e.upid) + ": expected " +
                                 std::to_string(e.value) + ", drive has " + std::to_string(actual));
      }
    }
    for (const auto& [upid, value] : on_drive) {
      rep.mismatches.push_back(lname + " " + hex4(upid) + ": modified on the drive (" +
                               std::to_string(value) + ") but not in the file");
    }
  }
  if (want.scope.command_table) {
    LMCFG_ASSIGN_OR_RETURN(auto ids, c.ct_defined_entries());
    std::vector<std::uint16_t> expected_ids;
    for (const auto& e : want.ct_entries) expected_ids.push_back(static_cast<std::uint16_t>(e.id));
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
  }
  if (want.scope.curves) {
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
  }
  return rep;
}

}  // namespace lmcfg::ops
