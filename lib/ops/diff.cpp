#include "ops/diff.hpp"

#include <algorithm>
#include <map>
#include <nlohmann/json.hpp>
#include <set>

#include "common/bytes.hpp"
#include "common/layers.hpp"
#include "db/ct_entry.hpp"
#include "db/database.hpp"
#include "db/value.hpp"
#include "ops/backup.hpp"
#include "ops/compare.hpp"
#include "ops/devicenet.hpp"
#include "ops/restore.hpp"

namespace lmcfg::ops {

namespace {

DiffItem make_item(DiffItem::Kind kind, std::string name, std::string a, std::string b,
                   std::string detail) {
  DiffItem it;
  it.kind = kind;
  it.name = std::move(name);
  it.a = std::move(a);
  it.b = std::move(b);
  it.detail = std::move(detail);
  return it;
}

// Why a value cannot be what its side says it is ("" = valid): it does not fit
// its type (shown raw, never truncated to the type's width), or it lies
// outside the database's min/max for that type.
std::string invalid_reason(const db::Parameter* d, std::optional<std::uint8_t> type,
                           std::uint32_t v) {
  std::optional<db::TypeCode> t;
  if (type) t = db::type_from_code(*type);
  if (!t && d) t = d->spec.type;
  if (!t)
    return type ? "type code " + std::to_string(*type) + " is not defined by seed 003 §10" : "";
  const auto i = db::field_integer(*t, v);
  if (!i) return "does not fit type " + std::string(db::type_name(*t));
  if (db::is_text_type(*t) || *t == db::TypeCode::LinFloat) return "";
  db::ValueSpec spec = d ? d->spec : db::ValueSpec{};
  if (spec.type && *spec.type != *t) spec.min = spec.max = std::nullopt;  // another type's range
  spec.type = *t;
  if (auto r = db::check_range(spec, *i); !r.ok()) return r.error().message;
  return "";
}

std::string raw_text(std::uint32_t v) {
  char buf[32];
  std::snprintf(buf, sizeof buf, "%u (%08Xh)", v, v);
  return buf;
}

std::string show(const ParamValue& v, const db::Database& db, std::uint16_t upid,
                 std::optional<std::uint32_t> def, std::optional<std::uint8_t> type,
                 const std::string& invalid) {
  auto fmt = [&](std::uint32_t x) { return display_value(db, upid, x, type); };
  switch (v.state) {
    case ParamValue::State::value:
      if (!v.value) return "not captured";
      if (invalid.empty()) return fmt(*v.value);
      if (invalid.rfind("does not fit", 0) == 0 || invalid.rfind("type code", 0) == 0)
        return raw_text(*v.value) + " INVALID: " + invalid;
      return fmt(*v.value) + " INVALID: " + invalid;
    case ParamValue::State::at_default:
      return def ? "default " + fmt(*def) : "default";
    case ParamValue::State::not_writable:
      return "absent";
  }
  return "";
}

std::string type_text(std::optional<std::uint8_t> t) {
  if (!t) return "";
  if (auto c = db::type_from_code(*t)) return std::string(db::type_name(*c));
  return "type code " + std::to_string(*t);
}

std::string layer_list(const std::array<bool, lmcfg::layers::kCount>& layers) {
  std::string s;
  for (int l = 1; l <= lmcfg::layers::kCount; ++l)
    if (layers[static_cast<std::size_t>(l - 1)])
      s += (s.empty() ? "" : ", ") + std::string(lmcfg::layers::name(l));
  return s.empty() ? "no layer" : s;
}

// A side's parameters of one layer for the comparison; without the
// communication parameters when they are not compared (--ignore-unit).
std::vector<config::Parameter> compared_params(const config::DriveConfig& c, int layer,
                                               const db::Database& db, const DiffOptions& opt) {
  std::vector<config::Parameter> out = c.layer(layer);
  if (opt.ignore_unit)
    std::erase_if(out, [&](const config::Parameter& p) { return is_comm_parameter(db, p.upid); });
  return out;
}

// One parameter that differs (or both sides hold the same invalid value: a
// note) as diff shows it.
void add_parameter(const ParamRow& row, const db::Database& db, DiffResult& r) {
  const std::uint16_t upid = row.upid;
  const db::Parameter* d = db.find(upid);
  const config::Parameter* pa = row.a.record;
  const config::Parameter* pb = row.b.record;
  const std::optional<std::uint8_t> rta = pa ? pa->type : std::nullopt;
  const std::optional<std::uint8_t> rtb = pb ? pb->type : std::nullopt;
  // Each side's value is shown and checked by its own recorded type (else the
  // other side's, else the database's).
  const auto ta = rta ? rta : rtb;
  const auto tb = rtb ? rtb : rta;
  const std::string bad_a = pa ? invalid_reason(d, ta, pa->value) : "";
  const std::string bad_b = pb ? invalid_reason(d, tb, pb->value) : "";
  std::string name = d && !d->name.empty() ? d->name : "";
  for (const auto* p : {pa, pb})
    if (name.empty() && p) name = p->name;
  const auto def = row.def.value;
  if (!row.differs()) {
    if (!bad_a.empty())
      r.notes.push_back(std::string(lmcfg::layers::name(row.layer)) + " " + hex(upid, 4, "h") +
                        (name.empty() ? "" : " " + name) + ": both sides hold the invalid value " +
                        show(row.a, db, upid, def, ta, bad_a));
    return;
  }
  DiffItem it;
  it.kind = DiffItem::Kind::parameter;
  it.layer = row.layer;
  it.key = upid;
  it.name = name;
  it.a = show(row.a, db, upid, def, ta, bad_a);
  it.b = show(row.b, db, upid, def, tb, bad_b);
  it.a_invalid = bad_a;
  it.b_invalid = bad_b;
  it.a_type = type_text(ta);
  it.b_type = type_text(tb);
  if (row.type_differs) it.detail = "type " + type_text(rta) + " -> " + type_text(rtb);
  r.items.push_back(std::move(it));
}

void diff_parameters(const config::DriveConfig& a, const config::DriveConfig& b,
                     const db::Database& db, const DefaultLookup& defaults, const DiffOptions& opt,
                     DiffResult& r) {
  std::size_t from_files = 0, from_lookup = 0;
  // Factory default: the rule (database, else a capture's record), else asked
  // (the tools ask a connected drive, 05h 07h).
  AskValue ask;
  if (defaults)
    ask = [&](std::uint16_t upid) -> Result<std::optional<std::uint32_t>> {
      return defaults(upid);
    };
  for (int layer = 1; layer <= 4; ++layer) {
    const bool in_a = a.scope.layers[static_cast<std::size_t>(layer - 1)];
    const bool in_b = b.scope.layers[static_cast<std::size_t>(layer - 1)];
    if (in_a != in_b) {
      const auto& holder = in_a ? a : b;
      DiffItem it;
      it.kind = DiffItem::Kind::scope;
      it.layer = layer;
      it.name = "layer " + std::string(lmcfg::layers::name(layer));
      it.a = in_a ? "captured" : "not captured";
      it.b = in_b ? "captured" : "not captured";
      it.detail = std::to_string(holder.layer(layer).size()) + " parameter(s) on the " +
                  (in_a ? "A" : "B") + " side not compared";
      r.items.push_back(std::move(it));
      continue;
    }
    if (!in_a) continue;
    const auto va = compared_params(a, layer, db, opt), vb = compared_params(b, layer, db, opt);
    const ParamSide sa{&va, a.scope.parameters, Resolve::rule_then_ask, ask};
    const ParamSide sb{&vb, b.scope.parameters, Resolve::rule_then_ask, ask};
    // ask never fails: the lookup keeps its own errors.
    const ParamCompare cmp = compare_parameters(layer, sa, sb, db).value();
    from_files += cmp.defaults_recorded;
    from_lookup += cmp.defaults_asked;
    for (const auto& row : cmp.rows) add_parameter(row, db, r);
  }
  if (from_files)
    r.notes.push_back(std::to_string(from_files) +
                      " default value(s) the UPID database does not know were taken from the "
                      "capture (the drive's own, "
                      "recorded at backup)");
  if (from_lookup)
    r.notes.push_back(
        std::to_string(from_lookup) +
        " default value(s) the UPID database does not know were asked from the drive (05h 07h)");
}

std::string curve_label(const config::Curve& c) {
  auto v = config::decode_curve(c);
  std::string s = "curve " + std::to_string(c.id);
  if (v.ok() && !v->name.empty()) s += " '" + v->name + "'";
  return s;
}

std::string curve_summary(const config::Curve& c) {
  auto v = config::decode_curve(c);
  if (!v.ok())
    return std::to_string(c.info.size()) + " B info, " + std::to_string(c.data.size()) + " B data";
  return std::to_string(v->setpoint_count) + " setpoints, " + v->length_ms_text() + " ms";
}

std::string curve_changes(const config::Curve& a, const config::Curve& b) {
  auto va = config::decode_curve(a);
  auto vb = config::decode_curve(b);
  if (!va.ok() || !vb.ok()) return "raw blocks differ";
  std::vector<std::string> parts;
  if (va->name != vb->name) parts.push_back("name '" + va->name + "' -> '" + vb->name + "'");
  if (va->setpoint_count != vb->setpoint_count)
    parts.push_back("setpoints " + std::to_string(va->setpoint_count) + " -> " +
                    std::to_string(vb->setpoint_count));
  if (va->length != vb->length)
    parts.push_back("length " + va->length_ms_text() + " ms -> " + vb->length_ms_text() + " ms");
  if (va->setpoints.size() == vb->setpoints.size()) {
    std::size_t n = 0, first = 0;
    for (std::size_t i = 0; i < va->setpoints.size(); ++i) {
      if (va->setpoints[i] != vb->setpoints[i]) {
        if (n++ == 0) first = i;
      }
    }
    if (n)
      parts.push_back(std::to_string(n) + " setpoint(s) differ, first #" +
                      std::to_string(first + 1));
  }
  if (parts.empty()) parts.push_back("info block bytes differ");
  std::string s;
  for (auto& p : parts) s += (s.empty() ? "" : ", ") + p;
  return s;
}

// How one side's scope holds a group: captured, not captured, or a drive
// that has no such group (config::Scope::drive_lacks).
std::string held_as(const config::Scope& s, bool in, const char* group) {
  if (in) return "captured";
  const bool lacks =
      std::find(s.drive_lacks.begin(), s.drive_lacks.end(), group) != s.drive_lacks.end();
  return lacks ? "not captured: the drive has no such group" : "not captured";
}

// A part captured on one side only: a difference, never "identical".
DiffItem scope_item(const char* what, const char* group, const config::DriveConfig& a,
                    const config::DriveConfig& b, bool in_a, bool in_b, const std::string& held) {
  return make_item(DiffItem::Kind::scope, what, held_as(a.scope, in_a, group),
                   held_as(b.scope, in_b, group),
                   held + " on the " + (in_a ? "A" : "B") + " side not compared");
}

void diff_curves(const config::DriveConfig& a, const config::DriveConfig& b, DiffResult& r) {
  if (a.scope.curves != b.scope.curves) {
    const auto& holder = a.scope.curves ? a : b;
    r.items.push_back(scope_item("curves", "curves", a, b, a.scope.curves, b.scope.curves,
                                 std::to_string(holder.curves.size()) + " curve(s)"));
    return;
  }
  if (!a.scope.curves) return;
  for (const auto& row : compare_curves(a.curves, b.curves)) {
    const auto* ca = row.a;
    const auto* cb = row.b;
    DiffItem it;
    it.kind = DiffItem::Kind::curve;
    it.key = row.id;
    it.name = curve_label(ca ? *ca : *cb);
    it.a = ca ? curve_summary(*ca) : "absent";
    it.b = cb ? curve_summary(*cb) : "absent";
    if (ca && cb) it.detail = curve_changes(*ca, *cb);
    r.items.push_back(std::move(it));
  }
}

std::string ct_changes(const db::Database& db, const config::CtEntry& a, const config::CtEntry& b) {
  if (db.is_empty()) return "raw bytes differ";
  auto da = db::decode_ct_entry(db, a.raw);
  auto dbb = db::decode_ct_entry(db, b.raw);
  if (!da.ok() || !dbb.ok()) return "raw bytes differ";
  if (!da->version_note.empty()) return "raw bytes differ; " + da->version_note;
  if (!dbb->version_note.empty()) return "raw bytes differ; " + dbb->version_note;
  std::vector<std::string> parts;
  if (da->header >> 4 != dbb->header >> 4) {
    parts.push_back(da->command_name + " -> " + dbb->command_name);
  } else {
    for (std::size_t i = 0; i < da->params.size() && i < dbb->params.size(); ++i) {
      if (da->params[i].raw != dbb->params[i].raw) {
        parts.push_back(db::summary_label(da->params[i].name) + " " + da->params[i].text + " -> " +
                        dbb->params[i].text);
      }
    }
  }
  if (da->link != dbb->link)
    parts.push_back("link " + hex(da->link, 4, "h") + " -> " + hex(dbb->link, 4, "h"));
  if (da->name != dbb->name) parts.push_back("name '" + da->name + "' -> '" + dbb->name + "'");
  if (parts.empty()) parts.push_back("undecoded bytes differ");
  std::string s;
  for (auto& p : parts) s += (s.empty() ? "" : ", ") + p;
  return s;
}

std::string ct_summary(const db::Database& db, const config::CtEntry& e) {
  if (!db.is_empty()) {
    auto d = db::decode_ct_entry(db, e.raw);
    if (d.ok()) return d->summary();
  }
  return std::to_string(e.raw.size()) + " bytes";
}

void diff_ct(const config::DriveConfig& a, const config::DriveConfig& b, const db::Database& db,
             DiffResult& r) {
  if (a.scope.command_table != b.scope.command_table) {
    const auto& holder = a.scope.command_table ? a : b;
    r.items.push_back(scope_item("command table", "command_table", a, b, a.scope.command_table,
                                 b.scope.command_table,
                                 std::to_string(holder.ct_entries.size()) + " entr(y/ies)"));
    return;
  }
  if (!a.scope.command_table) return;
  for (const auto& row : compare_ct_entries(a.ct_entries, b.ct_entries)) {
    const auto* ea = row.a;
    const auto* eb = row.b;
    DiffItem it;
    it.kind = DiffItem::Kind::ct_entry;
    it.key = row.id;
    it.name = config::ct_entry_name((ea ? ea : eb)->raw);
    it.a = ea ? ct_summary(db, *ea) : "absent";
    it.b = eb ? ct_summary(db, *eb) : "absent";
    if (ea && eb) it.detail = ct_changes(db, *ea, *eb);
    r.items.push_back(std::move(it));
  }
}

void diff_metadata(const config::Identity& a, const config::Identity& b, const DiffOptions& opt,
                   DiffResult& r) {
  auto cmp = [&](const char* field, const std::string& x, const std::string& y) {
    if (x != y) r.items.push_back(make_item(DiffItem::Kind::metadata, field, x, y, {}));
  };
  if (!opt.ignore_unit) cmp("macid", a.macid, b.macid);
  cmp("product", a.product, b.product);
  cmp("firmware", a.firmware, b.firmware);
  cmp("upid_fingerprint", a.upid_fingerprint, b.upid_fingerprint);
  std::set<std::string> keys;
  for (auto& [k, v] : a.labels) keys.insert(k);
  for (auto& [k, v] : b.labels) keys.insert(k);
  for (auto& k : keys) {
    auto ia = a.labels.find(k);
    auto ib = b.labels.find(k);
    cmp(("label " + k).c_str(), ia == a.labels.end() ? "" : ia->second,
        ib == b.labels.end() ? "" : ib->second);
  }
}

// ---------------------------------------------------------------------------
// DeviceNet controllers (seed 000).

void diff_dn_values(const std::vector<config::DevicenetValue>& a,
                    const std::vector<config::DevicenetValue>& b, bool live, const db::Database& db,
                    DiffResult& r) {
  using Key = std::pair<int, std::uint8_t>;
  std::map<Key, std::pair<const config::DevicenetValue*, const config::DevicenetValue*>> m;
  for (const auto& v : a) m[{v.motor, v.command}].first = &v;
  for (const auto& v : b) m[{v.motor, v.command}].second = &v;
  for (const auto& [key, sides] : m) {
    const auto [va, vb] = sides;
    // Raw words are the truth; display fields may come from another database.
    if (va && vb && va->raw == vb->raw) continue;
    DiffItem it;
    it.kind = DiffItem::Kind::devicenet;
    it.key = key.second;
    it.motor = key.first;
    it.live = live;
    it.name = devicenet_value_name(db, va ? *va : *vb);
    it.a = va ? devicenet_value_text(db, *va) : "absent";
    it.b = vb ? devicenet_value_text(db, *vb) : "absent";
    r.items.push_back(std::move(it));
  }
}

std::string motor_list(const std::vector<int>& motors) {
  std::string s;
  for (int m : motors) s += (s.empty() ? "" : ", ") + std::string(1, static_cast<char>('A' + m));
  return s;
}

std::string joined(const std::vector<std::string>& v) {
  std::string s;
  for (const auto& x : v) s += (s.empty() ? "" : ", ") + x;
  return s;
}

void diff_devicenet(const config::DevicenetSection& a, const config::DevicenetSection& b,
                    const db::Database& db, const DiffOptions& opt, DiffResult& r) {
  if (!opt.ignore_metadata) {
    auto cmp = [&](const char* field, const std::string& x, const std::string& y) {
      if (x != y) r.items.push_back(make_item(DiffItem::Kind::metadata, field, x, y, {}));
    };
    // The bit rate is the unit's place on its network, like its MAC ID.
    if (!opt.ignore_unit)
      cmp("devicenet can_bitrate", std::to_string(a.can_bitrate), std::to_string(b.can_bitrate));
    cmp("devicenet io_modules", joined(a.io_modules), joined(b.io_modules));
    cmp("devicenet motors", motor_list(a.motors), motor_list(b.motors));
  }
  diff_dn_values(a.values, b.values, false, db, r);
  if (opt.include_live) diff_dn_values(a.live, b.live, true, db, r);
}

// One side is a DeviceNet capture, the other is not: nothing to compare value
// by value. Says why in one scope item and a note.
void devicenet_mismatch(const config::DriveConfig& a, const config::DriveConfig& b,
                        const DiffOptions& opt, DiffResult& r) {
  const bool dn_a = a.devicenet.has_value();
  const char* dn_side = dn_a ? "A" : "B";
  const auto& dn = dn_a ? *a.devicenet : *b.devicenet;
  if (dn_a ? opt.b_is_defaults : opt.a_is_defaults) {
    // The database records no factory value for a Table 5-1 command: none is
    // invented in its place.
    r.items.push_back(make_item(
        DiffItem::Kind::scope, "devicenet values", dn_a ? "captured" : "no factory defaults",
        dn_a ? "no factory defaults" : "captured",
        std::to_string(dn.values.size()) + " value(s) on the " + dn_side + " side not compared"));
    r.notes.push_back(std::string(dn_side) +
                      " is a DeviceNet controller capture: lmcfg knows no factory defaults of "
                      "its values, so there is nothing to compare it with");
    return;
  }
  r.items.push_back(make_item(DiffItem::Kind::scope, "controller",
                              dn_a ? "DeviceNet controller" : "LinRS drive",
                              dn_a ? "LinRS drive" : "DeviceNet controller", "not comparable"));
  r.notes.push_back(dn_a ? "A is a DeviceNet controller capture, B a LinRS drive capture: not "
                           "comparable"
                         : "A is a LinRS drive capture, B a DeviceNet controller capture: not "
                           "comparable");
}

}  // namespace

const char* kind_name(DiffItem::Kind k) {
  switch (k) {
    case DiffItem::Kind::metadata:
      return "metadata";
    case DiffItem::Kind::parameter:
      return "parameter";
    case DiffItem::Kind::curve:
      return "curve";
    case DiffItem::Kind::ct_entry:
      return "ct_entry";
    case DiffItem::Kind::scope:
      return "scope";
    case DiffItem::Kind::devicenet:
      return "devicenet";
  }
  return "";
}

config::DriveConfig factory_defaults_config() {
  config::DriveConfig c;
  c.identity.product = "factory defaults";
  return c;
}

config::DriveConfig factory_defaults_config(const config::Scope& scope) {
  config::DriveConfig c = factory_defaults_config();
  c.scope = scope;
  c.scope.parameters = config::ParamSet::modified;
  return c;
}

std::string describe_scope(const config::Scope& s) {
  std::string out =
      std::string(config::to_string(s.parameters)) + " parameters of " + layer_list(s.layers);
  out += s.curves ? "; curves" : "; no curves";
  out += s.command_table ? "; command table" : "; no command table";
  return out;
}

DiffResult diff(const config::DriveConfig& a, const config::DriveConfig& b, const db::Database& db,
                const DefaultLookup& defaults, const DiffOptions& opt) {
  DiffResult r;
  r.scope_a = a.scope;
  r.scope_b = b.scope;
  for (std::size_t l = 0; l < r.compared.layers.size(); ++l)
    r.compared.layers[l] = a.scope.layers[l] && b.scope.layers[l];
  r.compared.parameters =
      a.scope.parameters == config::ParamSet::full && b.scope.parameters == config::ParamSet::full
          ? config::ParamSet::full
          : config::ParamSet::modified;
  r.compared.curves = a.scope.curves && b.scope.curves;
  r.compared.command_table = a.scope.command_table && b.scope.command_table;
  r.devicenet_a = a.devicenet.has_value();
  r.devicenet_b = b.devicenet.has_value();
  if (r.devicenet_a != r.devicenet_b) {
    devicenet_mismatch(a, b, opt, r);
    return r;
  }
  if (!opt.ignore_metadata) diff_metadata(a.identity, b.identity, opt, r);
  diff_parameters(a, b, db, defaults, opt, r);
  diff_curves(a, b, r);
  diff_ct(a, b, db, r);
  if (a.devicenet) {
    r.live_compared = opt.include_live;
    diff_devicenet(*a.devicenet, *b.devicenet, db, opt, r);
  }
  return r;
}

std::string render_text(const DiffResult& r, const std::string& an, const std::string& bn) {
  // A DeviceNet capture has no layers, curves or command table to describe.
  const auto side = [&](bool dn, const config::Scope& s) {
    if (!dn) return describe_scope(s);
    return std::string("DeviceNet controller values") + (r.live_compared ? " and live values" : "");
  };
  std::string out = "--- " + an + " (" + side(r.devicenet_a, r.scope_a) + ")\n+++ " + bn + " (" +
                    side(r.devicenet_b, r.scope_b) + ")\n";
  if (!(r.scope_a == r.scope_b) && r.devicenet_a == r.devicenet_b)
    out += "compared: " + describe_scope(r.compared) + "\n";
  std::string section;
  auto head = [&](const std::string& s) {
    if (s != section) {
      section = s;
      out += "\n" + s + ":\n";
    }
  };
  for (const auto& it : r.items) {
    switch (it.kind) {
      case DiffItem::Kind::metadata:
        head("identity");
        out += "  " + it.name + ": " + (it.a.empty() ? "(none)" : it.a) + " -> " +
               (it.b.empty() ? "(none)" : it.b) + "\n";
        break;
      case DiffItem::Kind::scope:
        head("scope");
        out += "  " + it.name + ": " + it.a + " -> " + it.b + " (" + it.detail + ")\n";
        break;
      case DiffItem::Kind::parameter:
        head(std::string("layer ") + std::string(lmcfg::layers::name(it.layer)));
        out += "  " + hex(it.key, 4, "h") + " " + (it.name.empty() ? "(name unknown)" : it.name) +
               ": " + it.a + " -> " + it.b + (it.detail.empty() ? "" : " (" + it.detail + ")") +
               "\n";
        break;
      case DiffItem::Kind::curve:
        head("curves");
        out += "  " + it.name + ": " + it.a + " -> " + it.b +
               (it.detail.empty() ? "" : " (" + it.detail + ")") + "\n";
        break;
      case DiffItem::Kind::ct_entry:
        head("command table");
        out += "  entry " + std::to_string(it.key) + (it.name.empty() ? "" : " '" + it.name + "'") +
               ": " + (it.detail.empty() ? it.a + " -> " + it.b : it.detail) + "\n";
        break;
      case DiffItem::Kind::devicenet:
        head(it.live ? "devicenet live" : "devicenet");
        out += "  " + it.name + ": " + it.a + " -> " + it.b + "\n";
        break;
    }
  }
  for (const auto& n : r.notes) out += "note: " + n + "\n";
  out +=
      r.identical() ? "\nidentical\n" : "\n" + std::to_string(r.items.size()) + " difference(s)\n";
  return out;
}

namespace {
nlohmann::ordered_json scope_json(const config::Scope& s) {
  nlohmann::ordered_json j;
  j["layers"] = nlohmann::ordered_json::array();
  for (int l = 1; l <= lmcfg::layers::kCount; ++l)
    if (s.layers[static_cast<std::size_t>(l - 1)]) j["layers"].push_back(lmcfg::layers::name(l));
  j["parameters"] = config::to_string(s.parameters);
  j["curves"] = s.curves;
  j["command_table"] = s.command_table;
  return j;
}
}  // namespace

std::string render_json(const DiffResult& r, const std::string& an, const std::string& bn) {
  nlohmann::ordered_json j;
  j["a"] = an;
  j["b"] = bn;
  j["identical"] = r.identical();
  j["scope"] = {{"a", scope_json(r.scope_a)},
                {"b", scope_json(r.scope_b)},
                {"compared", scope_json(r.compared)}};
  if (r.devicenet_a || r.devicenet_b)
    j["devicenet"] = {{"a", r.devicenet_a}, {"b", r.devicenet_b}, {"live", r.live_compared}};
  j["differences"] = nlohmann::ordered_json::array();
  for (const auto& it : r.items) {
    nlohmann::ordered_json d;
    d["kind"] = kind_name(it.kind);
    if (it.kind == DiffItem::Kind::parameter) {
      d["layer"] = std::string(lmcfg::layers::name(it.layer));
      d["upid"] = hex(it.key, 4, "h").substr(0, 4);
    } else if (it.kind == DiffItem::Kind::curve || it.kind == DiffItem::Kind::ct_entry) {
      d["id"] = it.key;
    } else if (it.kind == DiffItem::Kind::devicenet) {
      d["motor"] = it.motor == config::kDevicenetController
                       ? std::string("controller")
                       : std::string(1, static_cast<char>('A' + it.motor));
      d["command"] = hex(it.key, 2);
      if (it.live) d["live"] = true;
    }
    d["name"] = it.name;
    d["a"] = it.a;
    d["b"] = it.b;
    if (it.kind == DiffItem::Kind::parameter) {
      if (!it.a_type.empty()) d["a_type"] = it.a_type;
      if (!it.b_type.empty()) d["b_type"] = it.b_type;
      if (!it.a_invalid.empty()) d["a_invalid"] = it.a_invalid;
      if (!it.b_invalid.empty()) d["b_invalid"] = it.b_invalid;
    }
    if (!it.detail.empty()) d["detail"] = it.detail;
    j["differences"].push_back(std::move(d));
  }
  j["notes"] = r.notes;
  return j.dump(2) + "\n";
}

}  // namespace lmcfg::ops
