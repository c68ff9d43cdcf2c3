// The row validators of the UPID database compiler: every check of
// upid-db/FORMAT.md, reported at file:line:column.
#include <algorithm>
#include <cmath>
#include <cstdlib>
#include <map>
#include <optional>
#include <set>

#include "common/bytes.hpp"
#include "db/compiler_model.hpp"

namespace lmcfg::db::compiler {

namespace {

using tsv::Field;
using tsv::Row;
using tsv::Table;

std::optional<std::uint64_t> parse_hex_digits(std::string_view s, std::size_t min_digits,
                                              std::size_t max_digits) {
  if (s.size() < min_digits || s.size() > max_digits) return std::nullopt;
  std::uint64_t v = 0;
  for (char ch : s) {
    int d;
    if (ch >= '0' && ch <= '9')
      d = ch - '0';
    else if (ch >= 'A' && ch <= 'F')
      d = ch - 'A' + 10;
    else if (ch >= 'a' && ch <= 'f')
      d = ch - 'a' + 10;
    else
      return std::nullopt;
    v = v * 16 + static_cast<unsigned>(d);
  }
  return v;
}

// Column `col` of row `r` as hex of min_digits..max_digits digits; nullopt,
// with the error reported at the field ("bad hex ... (expected 4 hex digits,
// e.g. 13A2)"), when it is not.
std::optional<std::uint64_t> hex_column(const Table& t, const Row& r, std::string_view col,
                                        std::size_t min_digits, std::size_t max_digits,
                                        std::string_view example) {
  const Field& f = t.get(r, col);
  auto v = parse_hex_digits(f.text, min_digits, max_digits);
  if (!v) {
    const std::string digits =
        min_digits != max_digits
            ? std::to_string(min_digits) + " to " + std::to_string(max_digits) + " hex digits"
        : min_digits == 1 ? std::string("1 hex digit")
                          : std::to_string(min_digits) + " hex digits";
    t.error(r, f,
            "bad hex \"" + std::string(f.text) + "\" in column '" + std::string(col) +
                "' (expected " + digits + ", e.g. " + std::string(example) + ")");
  }
  return v;
}

std::optional<std::int64_t> parse_dec(std::string_view s) {
  bool neg = false;
  if (!s.empty() && (s[0] == '-' || s[0] == '+')) {
    neg = s[0] == '-';
    s.remove_prefix(1);
  }
  if (s.empty() || s.size() > 12) return std::nullopt;
  std::int64_t v = 0;
  for (char ch : s) {
    if (ch < '0' || ch > '9') return std::nullopt;
    v = v * 10 + (ch - '0');
  }
  return neg ? -v : v;
}

std::optional<double> parse_scale(std::string_view s) {
  std::string str(s);
  char* end = nullptr;
  double v = std::strtod(str.c_str(), &end);
  if (str.empty() || end != str.c_str() + str.size() || !std::isfinite(v) || v <= 0)
    return std::nullopt;
  return v;
}

std::string type_list() {
  std::string s;
  for (unsigned i = 0; i < 16; ++i)
    s += (i ? " " : "") + std::string(type_name(static_cast<TypeCode>(i)));
  return s;
}

// ---------------------------------------------------------------- rows

Provenance prov_of(const Table& t, const Row& r) {
  return Provenance{std::string(t.get(r, "source").text), t.name(), r.line};
}

bool require(const Table& t, const Row& r, std::string_view col, std::string_view what) {
  const Field& f = t.get(r, col);
  if (!f.text.empty()) return true;
  t.error(r, f, "missing " + std::string(what) + " in column '" + std::string(col) + "'");
  return false;
}

std::optional<TypeCode> read_type(const Table& t, const Row& r, bool required) {
  const Field& f = t.get(r, "type");
  if (f.text.empty()) {
    if (required) t.error(r, f, "missing type in column 'type'");
    return std::nullopt;
  }
  auto ty = type_from_name(f.text);
  if (!ty)
    t.error(
        r, f,
        "unknown type name \"" + std::string(f.text) + "\" (expected one of: " + type_list() + ")");
  return ty;
}

bool read_scale_unit(const Table& t, const Row& r, ValueSpec& spec) {
  spec.unit = std::string(t.get(r, "unit").text);
  const Field& sf = t.get(r, "scale");
  if (sf.text.empty()) return true;
  auto sc = parse_scale(sf.text);
  if (!sc) {
    t.error(r, sf,
            "bad scale \"" + std::string(sf.text) +
                "\" (expected a positive decimal number, e.g. 0.0001)");
    return false;
  }
  spec.scale = sc;
  return true;
}

// min, max (and default, when `def` is given): raw decimal values inside the
// type's range when the type is known; max not below min.
bool read_range(const Table& t, const Row& r, ValueSpec& spec, std::optional<std::int64_t>* def) {
  bool ok = true;
  for (const char* col : {"min", "max", "default"}) {
    if (col[0] == 'd' && !def) continue;
    const Field& f = t.get(r, col);
    if (f.text.empty()) continue;
    auto v = parse_dec(f.text);
    if (!v || *v < -2147483648ll || *v > 0xFFFFFFFFll) {
      t.error(r, f,
              "bad integer \"" + std::string(f.text) + "\" in column '" + col +
                  "' (expected a raw decimal value, -2147483648..4294967295)");
      ok = false;
      continue;
    }
    if (spec.type) {
      if (auto range = type_range(*spec.type); range && (*v < range->min || *v > range->max)) {
        t.error(r, f,
                std::string(col) + " " + std::to_string(*v) + " is outside the " +
                    std::string(type_name(*spec.type)) + " range " + std::to_string(range->min) +
                    ".." + std::to_string(range->max));
        ok = false;
        continue;
      }
    }
    if (col[1] == 'i')
      spec.min = v;
    else if (col[1] == 'a')
      spec.max = v;
    else
      *def = v;
  }
  if (spec.min && spec.max && *spec.min > *spec.max) {
    t.error(r, t.get(r, "max"),
            "max " + std::to_string(*spec.max) + " is below min " + std::to_string(*spec.min));
    ok = false;
  }
  return ok;
}

// Column 'enum': raw=Label items separated by |.
bool read_enum(const Table& t, const Row& r, ValueSpec& spec) {
  const Field& ef = t.get(r, "enum");
  if (ef.text.empty()) return true;
  bool ok = true;
  std::string_view rest = ef.text;
  std::set<std::int64_t> raws;
  while (true) {
    std::size_t bar = rest.find('|');
    std::string_view item = rest.substr(0, bar);
    std::size_t eq = item.find('=');
    std::optional<std::int64_t> raw =
        eq == std::string_view::npos ? std::nullopt : parse_dec(item.substr(0, eq));
    if (!raw || eq + 1 >= item.size()) {
      t.error(r, ef,
              "bad enum item \"" + std::string(item) +
                  "\" in column 'enum' (expected raw=Label, e.g. 1=By Parameter)");
      ok = false;
    } else if (!raws.insert(*raw).second) {
      t.error(r, ef, "enum value " + std::to_string(*raw) + " appears twice in column 'enum'");
      ok = false;
    } else {
      spec.labels.push_back({*raw, std::string(item.substr(eq + 1))});
    }
    if (bar == std::string_view::npos) break;
    rest = rest.substr(bar + 1);
  }
  return ok;
}

// A flag column: empty or exactly `mark`.
bool read_flag(const Table& t, const Row& r, std::string_view col, std::string_view mark,
               bool& out) {
  const Field& f = t.get(r, col);
  out = f.text == mark;
  if (f.text.empty() || out) return true;
  t.error(r, f,
          "bad value \"" + std::string(f.text) + "\" in column '" + std::string(col) +
              "' (expected " + std::string(mark) + " or empty)");
  return false;
}

void load_profiles(const Table& t, Model& m) {
  std::map<std::string, int> seen;
  for (const auto& r : t.rows()) {
    bool ok = require(t, r, "profile", "profile id");
    ok = require(t, r, "source", "source (provenance)") && ok;
    if (!ok) continue;
    Profile p;
    p.id = std::string(t.get(r, "profile").text);
    if (auto [it, inserted] = seen.emplace(p.id, r.line); !inserted) {
      t.error(r, t.get(r, "profile"),
              "duplicate profile \"" + p.id + "\" (first at " + t.name() + ":" +
                  std::to_string(it->second) + ")");
      continue;
    }
    p.family = std::string(t.get(r, "family").text);
    p.software = std::string(t.get(r, "software").text);
    p.version = std::string(t.get(r, "version").text);
    p.description = std::string(t.get(r, "description").text);
    p.prov = prov_of(t, r);
    m.profiles.push_back(std::move(p));
  }
}

// Column 'profiles' of parameters.tsv: a comma list of known profile ids, or *.
bool read_profiles(const Table& t, const Row& r, const std::set<std::string>& known, Parameter& p) {
  const Field& pf = t.get(r, "profiles");
  if (pf.text.empty()) {
    t.error(r, pf, "missing profile list in column 'profiles' (a comma list of profile ids, or *)");
    return false;
  }
  if (pf.text == "*") return true;
  bool ok = true;
  std::string_view rest = pf.text;
  while (true) {
    std::size_t comma = rest.find(',');
    std::string id(rest.substr(0, comma));
    while (!id.empty() && id.front() == ' ') id.erase(id.begin());
    while (!id.empty() && id.back() == ' ') id.pop_back();
    if (!known.count(id)) {
      t.error(r, pf, "unknown profile \"" + id + "\" in column 'profiles' (not in profiles.tsv)");
      ok = false;
    } else {
      p.profiles.push_back(id);
    }
    if (comma == std::string_view::npos) break;
    rest = rest.substr(comma + 1);
  }
  return ok;
}

// Column 'layer': a layer name that matches the UPID's range (`has_upid`: the
// UPID column was read).
bool read_layer(const Table& t, const Row& r, bool has_upid, Parameter& p) {
  const Field& lf = t.get(r, "layer");
  auto layer = layer_from_name(lf.text);
  if (!layer) {
    t.error(
        r, lf,
        "unknown layer \"" + std::string(lf.text) + "\" (expected OS, MC, Intf, Appl or Other)");
    return false;
  }
  if (!has_upid) return true;
  auto actual = layer_of_upid(p.upid);
  if (!actual && *layer != Layer::Other) {
    t.error(r, lf,
            "UPID " + hex(p.upid, 4) +
                " is outside every layer range (OS 0000-0EFF, MC 1000-1EFF, Intf 2000-2EFF, "
                "Appl 3000-3EFF): its layer must be Other");
    return false;
  }
  if (actual && *actual != *layer) {
    unsigned base = layer_base_upid(*actual);
    t.error(r, lf,
            "layer \"" + std::string(lf.text) + "\" does not match UPID " + hex(p.upid, 4) +
                " (in the " + std::string(layer_name(*actual)) + " range " + hex(base, 4) + "-" +
                hex(base + 0x0EFF, 4) + ")");
    return false;
  }
  p.layer = *layer;
  return true;
}

// Column 'address_usage': empty, or 4 hex digits.
bool read_address_usage(const Table& t, const Row& r, Parameter& p) {
  if (t.get(r, "address_usage").text.empty()) return true;
  auto au = hex_column(t, r, "address_usage", 4, 4, "000D");
  if (!au) return false;
  p.address_usage = AddressUsage{static_cast<std::uint16_t>(*au)};
  return true;
}

// The columns a UPID row (parameters.tsv) and a DeviceNet parameter row share:
// range and default, scale and unit, enum labels, the comm flag, the
// description and the provenance; false (errors reported) when one is bad.
template <class P>
bool read_value_columns(const Table& t, const Row& r, P& p) {
  bool ok = read_range(t, r, p.spec, &p.default_value);
  if (!read_scale_unit(t, r, p.spec)) ok = false;
  if (!read_enum(t, r, p.spec)) ok = false;
  if (!read_flag(t, r, "comm", "1", p.comm)) ok = false;
  p.description = std::string(t.get(r, "description").text);
  if (!require(t, r, "source", "source (provenance)")) ok = false;
  p.prov = prov_of(t, r);
  return ok;
}

// Every column of a parameters.tsv row into `p`; false (errors reported) when one is bad.
bool read_parameter(const Table& t, const Row& r, const std::set<std::string>& known,
                    Parameter& p) {
  bool ok = true;
  auto upid = hex_column(t, r, "upid", 4, 4, "13A2");
  if (!upid) {
    ok = false;
  } else {
    p.upid = static_cast<std::uint16_t>(*upid);
  }
  if (!read_profiles(t, r, known, p)) ok = false;
  if (!read_layer(t, r, upid.has_value(), p)) ok = false;
  p.name = std::string(t.get(r, "name").text);  // may be unknown (empty)
  p.path = std::string(t.get(r, "path").text);
  const Field& tf = t.get(r, "type");
  if (!tf.text.empty()) {
    p.spec.type = read_type(t, r, false);
    if (!p.spec.type) ok = false;
  }
  if (!read_address_usage(t, r, p)) ok = false;
  if (!read_value_columns(t, r, p)) ok = false;
  return ok;
}

// UPID -> (profile or "*", line) already defined.
using DefinedUpids = std::map<std::uint16_t, std::vector<std::pair<std::string, int>>>;

// A UPID defined twice for a profile ('*' overlaps every profile) is an error;
// otherwise the row's profiles are recorded in `defined`.
bool record_unique(const Table& t, const Row& r, const Parameter& p, DefinedUpids& defined) {
  auto& prev = defined[p.upid];
  std::vector<std::string> mine = p.profiles.empty() ? std::vector<std::string>{"*"} : p.profiles;
  for (const auto& [other, line] : prev) {
    for (const auto& id : mine) {
      if (id == other || id == "*" || other == "*") {
        std::string which = id == "*" ? other : id;
        t.error(r, t.get(r, "upid"),
                "duplicate UPID " + hex(p.upid, 4) +
                    (which == "*" ? std::string(" for every profile") : " for profile " + which) +
                    " (first at " + t.name() + ":" + std::to_string(line) + ")");
        return false;
      }
    }
  }
  for (const auto& id : mine) prev.emplace_back(id, r.line);
  return true;
}

void load_parameters(const Table& t, Model& m) {
  std::set<std::string> known;
  for (const auto& p : m.profiles) known.insert(p.id);
  DefinedUpids defined;
  for (const auto& r : t.rows()) {
    Parameter p;
    if (!read_parameter(t, r, known, p)) continue;
    if (!record_unique(t, r, p, defined)) continue;
    m.params.push_back(std::move(p));
  }
}

void load_errors(const Table& t, Model& m) {
  std::map<std::pair<std::string, std::uint32_t>, int> seen;
  for (const auto& r : t.rows()) {
    bool ok = true;
    ErrorEntry e;
    const Field& df = t.get(r, "domain");
    e.domain = std::string(df.text);
    if (e.domain.empty() || !std::all_of(e.domain.begin(), e.domain.end(), [](char ch) {
          return (ch >= 'a' && ch <= 'z') || (ch >= '0' && ch <= '9') || ch == '_' || ch == '-';
        })) {
      t.error(r, df,
              "bad domain \"" + e.domain + "\" (expected a lower-case id: mc, linrs, devicenet)");
      ok = false;
    }
    const Field& cf = t.get(r, "code");
    auto code = hex_column(t, r, "code", 1, 8, "000C");
    if (!code) {
      ok = false;
    } else {
      e.code = static_cast<std::uint32_t>(*code);
      e.code_text = std::string(cf.text);
    }
    e.text = std::string(t.get(r, "text").text);
    const Field& klass = t.get(r, "class");
    e.error_class = std::string(klass.text);
    static const std::set<std::string_view> kClasses = {
        "Err", "Fatal Err", "Cfg Err", "Cfg Err (Fatal)", "User Err", "Setup Err", "Runtime Err"};
    if (!e.error_class.empty() && !kClasses.count(e.error_class)) {
      t.error(r, klass,
              "unknown error class \"" + e.error_class +
                  "\" (expected Err, Fatal Err, Cfg Err, Cfg Err (Fatal), User Err, Setup Err, "
                  "Runtime Err or empty)");
      ok = false;
    } else if (!e.error_class.empty() && e.text.rfind(e.error_class + ":", 0) != 0) {
      t.error(r, klass,
              "error class \"" + e.error_class + "\" is not the prefix of the text \"" + e.text +
                  "\" (seed 001 §10 writes the class before a colon)");
      ok = false;
    }
    e.description = std::string(t.get(r, "description").text);
    e.action = std::string(t.get(r, "action").text);
    if (!require(t, r, "source", "source (provenance)")) ok = false;
    e.prov = prov_of(t, r);
    if (!ok) continue;
    if (auto [it, ins] = seen.emplace(std::make_pair(e.domain, e.code), r.line); !ins) {
      t.error(r, cf,
              "duplicate error code " + e.code_text + " in domain " + e.domain + " (first at " +
                  t.name() + ":" + std::to_string(it->second) + ")");
      continue;
    }
    m.errors.push_back(std::move(e));
  }
}

struct CmdKey {
  std::uint8_t master, sub;
  bool ok;
};

CmdKey read_cmd_key(const Table& t, const Row& r) {
  CmdKey k{0, 0, true};
  auto master = hex_column(t, r, "master", 2, 2, "01");
  if (!master) {
    k.ok = false;
  } else {
    k.master = static_cast<std::uint8_t>(*master);
  }
  auto sub = hex_column(t, r, "sub", 1, 1, "0");
  if (!sub) {
    k.ok = false;
  } else {
    k.sub = static_cast<std::uint8_t>(*sub);
  }
  return k;
}

std::string cmd_text(const CmdKey& k) {
  char b[16];
  std::snprintf(b, sizeof b, "%02X/%X", k.master, k.sub);
  return b;
}

void load_commands(const Table& t, Model& m) {
  std::map<std::uint16_t, int> seen;
  for (const auto& r : t.rows()) {
    CmdKey k = read_cmd_key(t, r);
    bool ok = k.ok;
    if (!require(t, r, "name", "command name")) ok = false;
    if (!require(t, r, "source", "source (provenance)")) ok = false;
    if (!ok) continue;
    MotionCommand c;
    c.master = k.master;
    c.sub = k.sub;
    c.name = std::string(t.get(r, "name").text);
    c.products = std::string(t.get(r, "products").text);
    c.description = std::string(t.get(r, "description").text);
    c.prov = prov_of(t, r);
    if (auto [it, ins] = seen.emplace(c.header(), r.line); !ins) {
      t.error(r, t.get(r, "master"),
              "duplicate motion command " + cmd_text(k) + " (first at " + t.name() + ":" +
                  std::to_string(it->second) + ")");
      continue;
    }
    m.commands.push_back(std::move(c));
  }
}

void load_command_params(const Table& t, Model& m) {
  std::map<std::pair<std::uint16_t, int>, int> seen;
  for (const auto& r : t.rows()) {
    CmdKey k = read_cmd_key(t, r);
    bool ok = k.ok;
    MotionCommand* cmd = nullptr;
    if (k.ok) {
      for (auto& c : m.commands)
        if (c.master == k.master && c.sub == k.sub) cmd = &c;
      if (!cmd) {
        t.error(r, t.get(r, "master"),
                "motion command " + cmd_text(k) + " is not in motion_commands.tsv");
        ok = false;
      }
    }
    MotionParam p;
    const Field& inf = t.get(r, "index");
    auto idx = parse_dec(inf.text);
    if (!idx || *idx < 1 || *idx > 16) {
      t.error(r, inf, "bad index \"" + std::string(inf.text) + "\" (expected 1..16)");
      ok = false;
    } else {
      p.index = static_cast<int>(*idx);
    }
    auto type = read_type(t, r, false);  // may be unknown (empty)
    if (!type && !t.get(r, "type").text.empty()) ok = false;
    p.spec.type = type;
    const Field& of = t.get(r, "offset");
    auto off = parse_dec(of.text);
    if (!off || *off < 2 || *off + (type ? type_size(*type) : 1u) > 34) {
      t.error(r, of,
              "bad offset \"" + std::string(of.text) +
                  "\" (expected the byte offset from the header, 2 or more, with the value ending "
                  "by byte 34)");
      ok = false;
    } else {
      p.offset = static_cast<int>(*off);
    }
    p.name = std::string(t.get(r, "name").text);  // may be unknown (empty)
    if (!read_scale_unit(t, r, p.spec)) ok = false;
    p.range_text = std::string(t.get(r, "range").text);
    if (!read_range(t, r, p.spec, nullptr)) ok = false;
    if (!p.range_text.empty() && !p.spec.min) {
      t.error(r, t.get(r, "range"),
              "range \"" + p.range_text + "\" needs its lower bound in column 'min'");
      ok = false;
    }
    if (!read_flag(t, r, "scaled", "1", p.scaled)) ok = false;
    if (p.scaled && !p.spec.unit.empty()) {
      t.error(r, t.get(r, "scaled"),
              "a Scaled parameter has no fixed unit (found unit \"" + p.spec.unit + "\")");
      ok = false;
    }
    if (!require(t, r, "source", "source (provenance)")) ok = false;
    p.prov = prov_of(t, r);
    if (!ok) continue;
    if (auto [it, ins] = seen.emplace(std::make_pair(cmd->header(), p.index), r.line); !ins) {
      t.error(r, inf,
              "duplicate parameter index " + std::to_string(p.index) + " for motion command " +
                  cmd_text(k) + " (first at " + t.name() + ":" + std::to_string(it->second) + ")");
      continue;
    }
    cmd->params.push_back(std::move(p));
  }
  for (auto& c : m.commands)
    std::sort(c.params.begin(), c.params.end(),
              [](const MotionParam& a, const MotionParam& b) { return a.index < b.index; });
}

bool check_devicenet_profile(const Table& t, const Model& m) {
  for (const auto& p : m.profiles)
    if (p.id == kDevicenetProfile) return true;
  t.file_error("profile \"" + std::string(kDevicenetProfile) +
               "\" is not in profiles.tsv; the seed 000 tables belong to it");
  return false;
}

// DeviceNet §3.1: rows addressed by tree path; type and most fields unknown.
void load_devicenet_parameters(const Table& t, Model& m) {
  if (!check_devicenet_profile(t, m)) return;
  std::map<std::string, int> seen;
  for (const auto& r : t.rows()) {
    bool ok = require(t, r, "id", "parameter id (tree path or name)");
    DevicenetParameter p;
    p.id = std::string(t.get(r, "id").text);
    p.name = std::string(t.get(r, "name").text);
    p.path = std::string(t.get(r, "path").text);
    p.spec.type = read_type(t, r, false);
    if (!p.spec.type && !t.get(r, "type").text.empty()) ok = false;
    if (!read_value_columns(t, r, p)) ok = false;
    if (!ok) continue;
    if (auto [it, ins] = seen.emplace(p.id, r.line); !ins) {
      t.error(r, t.get(r, "id"),
              "duplicate DeviceNet parameter \"" + p.id + "\" (first at " + t.name() + ":" +
                  std::to_string(it->second) + ")");
      continue;
    }
    m.dn_params.push_back(std::move(p));
  }
}

// DeviceNet §5.2 Table 5-1: command IDs 0x00..0x7F.
void load_devicenet_commands(const Table& t, Model& m) {
  if (!check_devicenet_profile(t, m)) return;
  std::map<int, int> seen;
  for (const auto& r : t.rows()) {
    bool ok = true;
    DevicenetCommand c;
    const Field& idf = t.get(r, "id");
    auto id = idf.text.size() == 4 && idf.text.substr(0, 2) == "0x"
                  ? parse_hex_digits(idf.text.substr(2), 2, 2)
                  : std::nullopt;
    if (!id || *id > 0x7F || idf.text[2] > '7' ||
        std::islower(static_cast<unsigned char>(idf.text[3]))) {
      t.error(r, idf,
              "bad command ID \"" + std::string(idf.text) +
                  "\" (expected 0x00..0x7F as Table 5-1 writes it, e.g. 0x1A)");
      ok = false;
    } else {
      c.id = static_cast<std::uint8_t>(*id);
      c.id_text = std::string(idf.text);
    }
    const Field& df = t.get(r, "direction");
    c.direction = std::string(df.text);
    if (!c.direction.empty() && c.direction != "get" && c.direction != "set") {
      t.error(r, df, "bad direction \"" + c.direction + "\" (expected get, set or empty)");
      ok = false;
    }
    if (!require(t, r, "name", "command name")) ok = false;
    c.name = std::string(t.get(r, "name").text);
    c.table_name = std::string(t.get(r, "table_name").text);
    c.range_text = std::string(t.get(r, "range").text);
    c.unit_text = std::string(t.get(r, "unit_text").text);
    if (!read_range(t, r, c.spec, nullptr)) ok = false;
    if (!read_scale_unit(t, r, c.spec)) ok = false;
    if (!read_enum(t, r, c.spec)) ok = false;
    if (!read_flag(t, r, "addressed", "x", c.addressed)) ok = false;
    if (!read_flag(t, r, "direct", "x", c.direct)) ok = false;
    c.description = std::string(t.get(r, "description").text);
    if (!require(t, r, "source", "source (provenance)")) ok = false;
    c.prov = prov_of(t, r);
    if (!ok) continue;
    if (auto [it, ins] = seen.emplace(c.id, r.line); !ins) {
      t.error(r, idf,
              "duplicate command ID " + c.id_text + " (first at " + t.name() + ":" +
                  std::to_string(it->second) + ")");
      continue;
    }
    m.dn_commands.push_back(std::move(c));
  }
  std::sort(m.dn_commands.begin(), m.dn_commands.end(),
            [](const DevicenetCommand& a, const DevicenetCommand& b) { return a.id < b.id; });
}

}  // namespace

void load_table(const Table& t, Model& m) {
  const std::string& name = t.name();
  if (name == "profiles.tsv")
    load_profiles(t, m);
  else if (name == "parameters.tsv")
    load_parameters(t, m);
  else if (name == "errors.tsv")
    load_errors(t, m);
  else if (name == "motion_commands.tsv")
    load_commands(t, m);
  else if (name == "motion_command_params.tsv")
    load_command_params(t, m);
  else if (name == "devicenet_parameters.tsv")
    load_devicenet_parameters(t, m);
  else
    load_devicenet_commands(t, m);
}

}  // namespace lmcfg::db::compiler
