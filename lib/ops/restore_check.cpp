// Restore phase 1, the checks: every value the plan will write against what
// the target can take (restore.hpp).
#include <algorithm>
#include <set>

#include "common/bytes.hpp"
#include "common/layers.hpp"
#include "db/database.hpp"
#include "ops/restore.hpp"
#include "ops/restore_internal.hpp"

namespace lmcfg::ops {

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

namespace detail {

namespace {

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

// The target's range is the truth (docs/restore.md): the database describes
// the firmware we know, the target may allow less (§10 05h 05h/06h). Sets
// spec's min/max from the target; false (a problem) when it refuses to say.
Result<bool> target_range(client::Client& c, db::TypeCode code, std::uint16_t upid,
                          const db::Parameter* d, const std::string& label, db::ValueSpec& spec,
                          Plan& plan) {
  auto mn = c.get_min(upid);
  auto mx = mn.ok() ? c.get_max(upid) : Result<std::uint32_t>(mn.error());
  if (!mn.ok() || !mx.ok()) {
    Error e = !mn.ok() ? std::move(mn).error() : std::move(mx).error();
    if (!refused(e)) return e;
    plan.problems.push_back(label + ": the target refused the min/max query: " + e.message);
    return false;
  }
  const auto tmin = db::field_integer(code, *mn), tmax = db::field_integer(code, *mx);
  if (d && (d->spec.min || d->spec.max) && (d->spec.min != tmin || d->spec.max != tmax)) {
    plan.notes.push_back(label + ": the target's range " + range_text(tmin, tmax) +
                         " differs from the UPID database's " +
                         range_text(d->spec.min, d->spec.max) + "; the target's applies");
  }
  spec.min = tmin;
  spec.max = tmax;
  return true;
}

}  // namespace

namespace {
// LinUDP has no type request (LinUDP V2 p14): the file's type, else the
// database's; without either the range cannot be checked (a 16-bit value's
// sign is unknown) and the drive's refusal is what stops a bad write.
std::uint16_t type_without_request(const config::Parameter& p, const db::Parameter* d,
                                   bool& unknown) {
  if (p.type) return *p.type;
  if (d && d->spec.type) return type_code(*d->spec.type);
  unknown = true;
  return type_code(TypeCode::SInt32);
}
}  // namespace

// Checks one parameter the restore will write against the target; appends
// problems or incompatible values (and notes where the database disagrees
// with the target). True when the target can take it. Link errors propagate.
// `listed`: the target's UPID list of the layer (§10.3), read when the
// database does not know every address usage; else the type is asked.
Result<bool> check_parameter(client::Client& c, const db::Database& db, const RestoreOptions& opt,
                             int layer, const config::Parameter& p,
                             const std::map<std::uint16_t, client::UpidInfo>* listed,
                             const std::map<std::uint16_t, std::uint16_t>* usage, Plan& plan) {
  const db::Parameter* d = db.find(p.upid);
  const std::string label = param_label(layer, p.upid, d, &p);
  auto cannot = [&](Incompatibility r, std::string why) {
    incompatible(plan, opt,
                 skipped_value(SkippedValue::Kind::parameter, layer, p.upid,
                               param_name(p.upid, d, &p), label, r, std::move(why)));
    return false;
  };
  std::uint16_t type = 0;
  const bool typed = c.capabilities().parameter_type;
  std::optional<db::AddressUsage> address_usage;
  const char* au_source = "the UPID database's";
  if (d) address_usage = d->address_usage;
  if (!address_usage && usage) {
    if (auto it = usage->find(p.upid); it != usage->end()) {
      address_usage = db::AddressUsage{it->second};
      au_source = "the target's";
    }
  }
  if (listed) {
    auto it = listed->find(p.upid);
    if (it == listed->end()) {
      return cannot(Incompatibility::upid_absent, "UPID does not exist on the target (not in its " +
                                                      std::string(lmcfg::layers::name(layer)) +
                                                      " UPID list, §10.3)");
    }
    if (typed) type = it->second.type;
    if (!address_usage) {
      address_usage = db::AddressUsage{it->second.address_usage};
      au_source = "the target's";
    }
  } else if (typed) {
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
  bool type_unknown = false;
  if (!typed) type = type_without_request(p, d, type_unknown);
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
  if (type_unknown) {
    plan.notes.push_back(label + ": type unknown (" + c.capabilities().protocol +
                         " cannot ask it, LinUDP V2 p14; not in the file or the UPID "
                         "database): range not checked before writing");
    return true;
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
    LMCFG_ASSIGN_OR_RETURN(const bool known, target_range(c, *code, p.upid, d, label, spec, plan));
    if (!known) return false;
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

}  // namespace detail
}  // namespace lmcfg::ops
