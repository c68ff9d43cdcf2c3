#include "db/compiler.hpp"

#include <sqlite3.h>
#include <unistd.h>

#include <algorithm>
#include <cctype>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <optional>
#include <set>
#include <sstream>

#include "common/bytes.hpp"
#include "db/database.hpp"
#include "db/schema.hpp"

namespace lmcfg::db {

namespace fs = std::filesystem;

std::string Diagnostic::str() const {
  return file + ":" + std::to_string(line) + ":" + std::to_string(column) +
         (warning ? ": warning: " : ": error: ") + message;
}

bool CompileReport::ok() const {
  return std::none_of(diagnostics.begin(), diagnostics.end(),
                      [](const Diagnostic& d) { return !d.warning; });
}

std::uint64_t fnv1a64(std::string_view data, std::uint64_t h) noexcept {
  for (unsigned char c : data) {
    h ^= c;
    h *= 0x100000001b3ull;
  }
  return h;
}

const std::vector<std::string>& upid_db_source_files() {
  static const std::vector<std::string> k = {"profiles.tsv",
                                             "parameters.tsv",
                                             "errors.tsv",
                                             "motion_commands.tsv",
                                             "motion_command_params.tsv",
                                             "devicenet_parameters.tsv",
                                             "devicenet_commands.tsv"};
  return k;
}

namespace {

// ---------------------------------------------------------------- TSV reading

struct Field {
  std::string_view text;
  int column = 1;
};

struct Row {
  int line = 0;
  std::vector<Field> fields;
  int end_column = 1;  // column just after the last character
};

int char_column(std::string_view line, std::size_t byte_off) {
  int col = 1;
  for (std::size_t i = 0; i < byte_off && i < line.size(); ++i)
    if ((static_cast<unsigned char>(line[i]) & 0xC0) != 0x80) ++col;
  return col;
}

class Table;

class Compiler {
 public:
  explicit Compiler(CompileReport& rep) : rep_(rep) {}
  void error(const std::string& file, int line, int col, std::string msg) {
    rep_.diagnostics.push_back({file, line, col, std::move(msg), false});
  }
  void warning(const std::string& file, int line, int col, std::string msg) {
    rep_.diagnostics.push_back({file, line, col, std::move(msg), true});
  }
  CompileReport& rep_;
};

// One TSV file: header, rows, and column lookup by name.
class Table {
 public:
  Table(Compiler& c, std::string path, std::string name, std::string content,
        const std::vector<std::string>& columns)
      : c_(c), path_(std::move(path)), name_(std::move(name)), content_(std::move(content)) {
    parse(columns);
  }
  const std::vector<Row>& rows() const { return rows_; }
  const std::string& path() const { return path_; }
  const std::string& name() const { return name_; }
  bool header_ok() const { return header_ok_; }

  // Field by column name (header must have been validated).
  const Field& get(const Row& r, std::string_view col) const {
    for (std::size_t i = 0; i < header_.size(); ++i)
      if (header_[i] == col) return r.fields[i];
    static const Field kEmpty{};
    return kEmpty;
  }
  void error(const Row& r, const Field& f, std::string msg) const {
    c_.error(path_, r.line, f.column, std::move(msg));
  }
  void file_error(std::string msg) const { c_.error(path_, 1, 1, std::move(msg)); }

 private:
  void parse(const std::vector<std::string>& columns) {
    std::string_view all(content_);
    if (all.substr(0, 3) == "\xEF\xBB\xBF") all.remove_prefix(3);
    int line_no = 0;
    bool have_header = false;
    std::size_t header_line = 0;
    while (!all.empty()) {
      ++line_no;
      std::size_t nl = all.find('\n');
      std::string_view line = all.substr(0, nl);
      all = nl == std::string_view::npos ? std::string_view() : all.substr(nl + 1);
      if (!line.empty() && line.back() == '\r') line.remove_suffix(1);
      if (line.empty() || line[0] == '#') continue;
      std::string_view rest = line;
      if (std::all_of(line.begin(), line.end(), [](char ch) { return ch == ' ' || ch == '\t'; }))
        continue;
      Row r;
      r.line = line_no;
      std::size_t off = 0;
      while (true) {
        std::size_t tab = rest.find('\t');
        r.fields.push_back({rest.substr(0, tab), char_column(line, off)});
        if (tab == std::string_view::npos) break;
        off += tab + 1;
        rest = rest.substr(tab + 1);
      }
      r.end_column = char_column(line, line.size());
      if (!have_header) {
        have_header = true;
        header_line = static_cast<std::size_t>(line_no);
        check_header(r, columns);
        continue;
      }
      if (!header_ok_) continue;
      if (r.fields.size() != header_.size()) {
        int col = r.fields.size() > header_.size() ? r.fields[header_.size()].column : r.end_column;
        c_.error(path_, r.line, col,
                 "expected " + std::to_string(header_.size()) + " fields (as in the header, line " +
                     std::to_string(header_line) + "), found " + std::to_string(r.fields.size()));
        continue;
      }
      rows_.push_back(std::move(r));
    }
    if (!have_header) header_ok_ = false;
  }

  void check_header(const Row& r, const std::vector<std::string>& columns) {
    std::set<std::string> seen;
    for (const auto& f : r.fields) {
      std::string h(f.text);
      if (std::find(columns.begin(), columns.end(), h) == columns.end()) {
        std::string expected;
        for (const auto& c : columns) expected += (expected.empty() ? "" : " ") + c;
        c_.error(path_, r.line, f.column,
                 "unknown column \"" + h + "\" in the header (expected: " + expected + ")");
        header_ok_ = false;
      } else if (!seen.insert(h).second) {
        c_.error(path_, r.line, f.column, "column \"" + h + "\" appears twice in the header");
        header_ok_ = false;
      }
      header_.push_back(h);
    }
    for (const auto& c : columns) {
      if (!seen.count(c)) {
        c_.error(path_, r.line, r.end_column, "header lacks column \"" + c + "\"");
        header_ok_ = false;
      }
    }
  }

  Compiler& c_;
  std::string path_, name_, content_;
  std::vector<std::string> header_;
  std::vector<Row> rows_;
  bool header_ok_ = true;
};

// ---------------------------------------------------------------- field parsers

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

// ---------------------------------------------------------------- the model

struct Model {
  std::vector<Profile> profiles;
  std::vector<Parameter> params;
  std::vector<ErrorEntry> errors;
  std::vector<MotionCommand> commands;
  std::vector<DevicenetParameter> dn_params;
  std::vector<DevicenetCommand> dn_commands;
};

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

void load_parameters(const Table& t, Model& m) {
  std::set<std::string> known;
  for (const auto& p : m.profiles) known.insert(p.id);
  // UPID -> (profile or "*", line) already defined.
  std::map<std::uint16_t, std::vector<std::pair<std::string, int>>> defined;
  for (const auto& r : t.rows()) {
    bool ok = true;
    Parameter p;
    const Field& uf = t.get(r, "upid");
    auto upid = parse_hex_digits(uf.text, 4, 4);
    if (!upid) {
      t.error(r, uf,
              "bad hex \"" + std::string(uf.text) +
                  "\" in column 'upid' (expected 4 hex digits, e.g. 13A2)");
      ok = false;
    } else {
      p.upid = static_cast<std::uint16_t>(*upid);
    }
    // profiles
    const Field& pf = t.get(r, "profiles");
    if (pf.text.empty()) {
      t.error(r, pf,
              "missing profile list in column 'profiles' (a comma list of profile ids, or *)");
      ok = false;
    } else if (pf.text != "*") {
      std::string_view rest = pf.text;
      while (true) {
        std::size_t comma = rest.find(',');
        std::string id(rest.substr(0, comma));
        while (!id.empty() && id.front() == ' ') id.erase(id.begin());
        while (!id.empty() && id.back() == ' ') id.pop_back();
        if (!known.count(id)) {
          t.error(r, pf,
                  "unknown profile \"" + id + "\" in column 'profiles' (not in profiles.tsv)");
          ok = false;
        } else {
          p.profiles.push_back(id);
        }
        if (comma == std::string_view::npos) break;
        rest = rest.substr(comma + 1);
      }
    }
    // layer
    const Field& lf = t.get(r, "layer");
    auto layer = layer_from_name(lf.text);
    if (!layer) {
      t.error(r, lf,
              "unknown layer \"" + std::string(lf.text) +
                  "\" (expected OS, MC, Intf, Appl or Other)");
      ok = false;
    } else if (upid) {
      auto actual = layer_of_upid(p.upid);
      if (!actual && *layer != Layer::Other) {
        t.error(r, lf,
                "UPID " + hex(p.upid, 4) +
                    " is outside every layer range (OS 0000-0EFF, MC 1000-1EFF, Intf 2000-2EFF, "
                    "Appl 3000-3EFF): its layer must be Other");
        ok = false;
      } else if (actual && *actual != *layer) {
        unsigned base = layer_base_upid(*actual);
        t.error(r, lf,
                "layer \"" + std::string(lf.text) + "\" does not match UPID " + hex(p.upid, 4) +
                    " (in the " + std::string(layer_name(*actual)) + " range " + hex(base, 4) + "-" +
                    hex(base + 0x0EFF, 4) + ")");
        ok = false;
      } else {
        p.layer = *layer;
      }
    }
    p.name = std::string(t.get(r, "name").text);  // may be unknown (empty)
    p.path = std::string(t.get(r, "path").text);
    const Field& tf = t.get(r, "type");
    if (!tf.text.empty()) {
      p.spec.type = read_type(t, r, false);
      if (!p.spec.type) ok = false;
    }
    const Field& af = t.get(r, "address_usage");
    if (!af.text.empty()) {
      auto au = parse_hex_digits(af.text, 4, 4);
      if (!au) {
        t.error(r, af,
                "bad hex \"" + std::string(af.text) +
                    "\" in column 'address_usage' (expected 4 hex digits, e.g. 000D)");
        ok = false;
      } else {
        p.address_usage = AddressUsage{static_cast<std::uint16_t>(*au)};
      }
    }
    if (!read_range(t, r, p.spec, &p.default_value)) ok = false;
    if (!read_scale_unit(t, r, p.spec)) ok = false;
    if (!read_enum(t, r, p.spec)) ok = false;
    if (!read_flag(t, r, "comm", "1", p.comm)) ok = false;
    p.description = std::string(t.get(r, "description").text);
    if (!require(t, r, "source", "source (provenance)")) ok = false;
    p.prov = prov_of(t, r);
    if (!ok) continue;
    // Duplicate UPID per profile: '*' overlaps every profile.
    auto& prev = defined[p.upid];
    std::vector<std::string> mine = p.profiles.empty() ? std::vector<std::string>{"*"} : p.profiles;
    bool dup = false;
    for (const auto& [other, line] : prev) {
      for (const auto& id : mine) {
        if (id == other || id == "*" || other == "*") {
          std::string which = id == "*" ? other : id;
          t.error(r, uf,
                  "duplicate UPID " + hex(p.upid, 4) +
                      (which == "*" ? std::string(" for every profile") : " for profile " + which) +
                      " (first at " + t.name() + ":" + std::to_string(line) + ")");
          dup = true;
          break;
        }
      }
      if (dup) break;
    }
    if (dup) continue;
    for (const auto& id : mine) prev.emplace_back(id, r.line);
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
    auto code = parse_hex_digits(cf.text, 1, 8);
    if (!code) {
      t.error(r, cf,
              "bad hex \"" + std::string(cf.text) +
                  "\" in column 'code' (expected 1 to 8 hex digits, e.g. 000C)");
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
  const Field& mf = t.get(r, "master");
  auto master = parse_hex_digits(mf.text, 2, 2);
  if (!master) {
    t.error(r, mf,
            "bad hex \"" + std::string(mf.text) +
                "\" in column 'master' (expected 2 hex digits, e.g. 01)");
    k.ok = false;
  } else {
    k.master = static_cast<std::uint8_t>(*master);
  }
  const Field& sf = t.get(r, "sub");
  auto sub = parse_hex_digits(sf.text, 1, 1);
  if (!sub) {
    t.error(
        r, sf,
        "bad hex \"" + std::string(sf.text) + "\" in column 'sub' (expected 1 hex digit, e.g. 0)");
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

// Seed 000 §3.1: rows addressed by tree path; type and most fields unknown.
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
    if (!read_range(t, r, p.spec, &p.default_value)) ok = false;
    if (!read_scale_unit(t, r, p.spec)) ok = false;
    if (!read_enum(t, r, p.spec)) ok = false;
    if (!read_flag(t, r, "comm", "1", p.comm)) ok = false;
    p.description = std::string(t.get(r, "description").text);
    if (!require(t, r, "source", "source (provenance)")) ok = false;
    p.prov = prov_of(t, r);
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

// Seed 000 §5.2 Table 5-1: command IDs 0x00..0x7F.
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

const std::map<std::string, std::vector<std::string>>& columns_of() {
  static const std::map<std::string, std::vector<std::string>> k = {
      {"profiles.tsv", {"profile", "family", "software", "version", "description", "source"}},
      {"parameters.tsv",
       {"upid", "profiles", "layer", "name", "path", "type", "address_usage", "min", "max",
        "default", "unit", "scale", "enum", "comm", "description", "source"}},
      {"errors.tsv", {"domain", "code", "class", "text", "description", "action", "source"}},
      {"motion_commands.tsv", {"master", "sub", "name", "products", "description", "source"}},
      {"motion_command_params.tsv",
       {"master", "sub", "index", "offset", "name", "type", "unit", "scale", "range", "min",
        "max", "scaled", "source"}},
      {"devicenet_parameters.tsv",
       {"id", "name", "path", "type", "min", "max", "default", "unit", "scale", "enum", "comm",
        "description", "source"}},
      {"devicenet_commands.tsv",
       {"id", "direction", "name", "table_name", "range", "min", "max", "unit", "scale",
        "unit_text", "addressed", "direct", "enum", "description", "source"}},
  };
  return k;
}

// ---------------------------------------------------------------- writing

class Writer {
 public:
  explicit Writer(sqlite3* db) : db_(db) {}
  bool exec(const char* sql) {
    char* err = nullptr;
    if (sqlite3_exec(db_, sql, nullptr, nullptr, &err) != SQLITE_OK) {
      error_ = err ? err : "sqlite error";
      sqlite3_free(err);
      return false;
    }
    return true;
  }
  sqlite3_stmt* prepare(const char* sql) {
    sqlite3_stmt* s = nullptr;
    if (sqlite3_prepare_v2(db_, sql, -1, &s, nullptr) != SQLITE_OK) {
      error_ = sqlite3_errmsg(db_);
      return nullptr;
    }
    return s;
  }
  const std::string& error() const { return error_; }

 private:
  sqlite3* db_;
  std::string error_;
};

// Binds 1-based parameters; empty strings and nullopts become NULL.
struct Binder {
  sqlite3_stmt* s;
  int i = 0;
  Binder& text(const std::string& v) {
    ++i;
    if (v.empty())
      sqlite3_bind_null(s, i);
    else
      sqlite3_bind_text(s, i, v.c_str(), static_cast<int>(v.size()), SQLITE_TRANSIENT);
    return *this;
  }
  Binder& integer(std::optional<std::int64_t> v) {
    ++i;
    if (v)
      sqlite3_bind_int64(s, i, *v);
    else
      sqlite3_bind_null(s, i);
    return *this;
  }
  Binder& real(std::optional<double> v) {
    ++i;
    if (v)
      sqlite3_bind_double(s, i, *v);
    else
      sqlite3_bind_null(s, i);
    return *this;
  }
  Binder& prov(const Provenance& p) { return text(p.source).text(p.file).integer(p.line); }
  bool step() {
    int rc = sqlite3_step(s);
    sqlite3_reset(s);
    sqlite3_clear_bindings(s);
    i = 0;
    return rc == SQLITE_DONE;
  }
};

std::optional<std::int64_t> opt_bit(const std::optional<AddressUsage>& au, unsigned bit) {
  if (!au) return std::nullopt;
  return (au->raw >> bit) & 1u;
}

std::string write_db(const Model& m, const std::string& path, const std::string& hash,
                     const std::string& built_from) {
  sqlite3* db = nullptr;
  if (sqlite3_open_v2(path.c_str(), &db, SQLITE_OPEN_READWRITE | SQLITE_OPEN_CREATE, nullptr) !=
      SQLITE_OK) {
    std::string e = db ? sqlite3_errmsg(db) : "out of memory";
    sqlite3_close(db);
    return "cannot create " + path + ": " + e;
  }
  Writer w(db);
  std::vector<sqlite3_stmt*> stmts;
  auto fail = [&](const std::string& what) {
    for (auto* s : stmts) sqlite3_finalize(s);
    sqlite3_close(db);
    return "writing " + path + ": " + what + ": " + w.error();
  };
  if (!w.exec("PRAGMA journal_mode=OFF; PRAGMA synchronous=OFF;") || !w.exec(kSchemaSql) ||
      !w.exec("BEGIN"))
    return fail("schema");
  auto prep = [&](const char* sql) {
    sqlite3_stmt* s = w.prepare(sql);
    if (s) stmts.push_back(s);
    return s;
  };
  sqlite3_stmt* meta = prep("INSERT INTO meta(key, value) VALUES(?, ?)");
  sqlite3_stmt* prof = prep("INSERT INTO profiles VALUES(?,?,?,?,?,?,?,?)");
  sqlite3_stmt* par = prep(
      "INSERT INTO parameters(id, upid, upid_hex, profiles, layer, name, path, type_code, type, "
      "address_usage, "
      "ram_read, ram_write, rom_read, rom_write, no_hash, min, max, default_value, unit, scale, "
      "comm, description, "
      "source, src_file, src_line) VALUES(?,?,?,?,?,?,?,?,?,?,?,?,?,?,?,?,?,?,?,?,?,?,?,?,?)");
  sqlite3_stmt* lab = prep("INSERT INTO enum_labels VALUES(?,?,?,?,?,?)");
  sqlite3_stmt* err = prep("INSERT INTO errors VALUES(?,?,?,?,?,?,?,?,?,?)");
  sqlite3_stmt* cmd = prep("INSERT INTO motion_commands VALUES(?,?,?,?,?,?,?,?,?)");
  sqlite3_stmt* cpar =
      prep("INSERT INTO motion_command_params VALUES(?,?,?,?,?,?,?,?,?,?,?,?,?,?,?,?)");
  sqlite3_stmt* dnp =
      prep("INSERT INTO devicenet_parameters VALUES(?,?,?,?,?,?,?,?,?,?,?,?,?,?,?,?,?)");
  sqlite3_stmt* dnpl = prep("INSERT INTO devicenet_parameter_labels VALUES(?,?,?,?,?,?)");
  sqlite3_stmt* dnc =
      prep("INSERT INTO devicenet_commands VALUES(?,?,?,?,?,?,?,?,?,?,?,?,?,?,?,?,?,?)");
  sqlite3_stmt* dncl = prep("INSERT INTO devicenet_command_labels VALUES(?,?,?,?,?,?)");
  if (!meta || !prof || !par || !lab || !err || !cmd || !cpar || !dnp || !dnpl || !dnc || !dncl)
    return fail("prepare");
  auto add_meta = [&](const std::string& k, const std::string& v) {
    return Binder{meta}.text(k).text(v).step();
  };
  if (!add_meta("schema_version", std::to_string(kSchemaVersion)) ||
      !add_meta("content_hash", hash) || !add_meta("built_from", built_from) ||
      !add_meta("generator", "upiddb-compile"))
    return fail("meta");
  for (const auto& p : m.profiles)
    if (!Binder{prof}
             .text(p.id)
             .text(p.family)
             .text(p.software)
             .text(p.version)
             .text(p.description)
             .prov(p.prov)
             .step())
      return fail("profiles");
  std::int64_t id = 0;
  for (const auto& p : m.params) {
    ++id;
    std::string profiles;
    for (const auto& s : p.profiles) profiles += (profiles.empty() ? "" : ",") + s;
    if (profiles.empty()) profiles = "*";
    std::optional<std::int64_t> tc;
    std::string tn;
    if (p.spec.type) {
      tc = static_cast<std::int64_t>(*p.spec.type);
      tn = std::string(type_name(*p.spec.type));
    }
    std::optional<std::int64_t> au;
    if (p.address_usage) au = p.address_usage->raw;
    Binder b{par};
    b.integer(id)
        .integer(p.upid)
        .text(hex(p.upid, 4))
        .text(profiles)
        .text(std::string(layer_name(p.layer)))
        .text(p.name)
        .text(p.path)
        .integer(tc)
        .text(tn)
        .integer(au);
    b.integer(opt_bit(p.address_usage, 0))
        .integer(opt_bit(p.address_usage, 1))
        .integer(opt_bit(p.address_usage, 2))
        .integer(opt_bit(p.address_usage, 3))
        .integer(opt_bit(p.address_usage, 12));
    b.integer(p.spec.min)
        .integer(p.spec.max)
        .integer(p.default_value)
        .text(p.spec.unit)
        .real(p.spec.scale)
        .integer(p.comm ? 1 : 0)
        .text(p.description)
        .prov(p.prov);
    if (!b.step()) return fail("parameters");
    for (const auto& l : p.spec.labels)
      if (!Binder{lab}.integer(id).integer(l.raw).text(l.label).prov(p.prov).step())
        return fail("enum_labels");
  }
  for (const auto& e : m.errors)
    if (!Binder{err}
             .text(e.domain)
             .integer(e.code)
             .text(e.code_text)
             .text(e.text)
             .text(e.description)
             .text(e.action)
             .text(e.error_class)
             .prov(e.prov)
             .step())
      return fail("errors");
  for (const auto& c : m.commands) {
    if (!Binder{cmd}
             .integer(c.master)
             .integer(c.sub)
             .integer(c.header())
             .text(c.name)
             .text(c.products)
             .text(c.description)
             .prov(c.prov)
             .step())
      return fail("motion_commands");
    for (const auto& p : c.params) {
      std::optional<std::int64_t> tc;
      if (p.spec.type) tc = static_cast<std::int64_t>(*p.spec.type);
      if (!Binder{cpar}
               .integer(c.master)
               .integer(c.sub)
               .integer(p.index)
               .integer(p.offset)
               .text(p.name)
               .integer(tc)
               .text(p.spec.type ? std::string(type_name(*p.spec.type)) : std::string())
               .text(p.spec.unit)
               .real(p.spec.scale)
               .text(p.range_text)
               .integer(p.spec.min)
               .integer(p.spec.max)
               .integer(p.scaled ? 1 : 0)
               .prov(p.prov)
               .step())
        return fail("motion_command_params");
    }
  }
  const std::string dn_profile(kDevicenetProfile);
  auto type_code_of = [](const ValueSpec& s) -> std::optional<std::int64_t> {
    if (!s.type) return std::nullopt;
    return static_cast<std::int64_t>(*s.type);
  };
  auto type_text_of = [](const ValueSpec& s) {
    return s.type ? std::string(type_name(*s.type)) : std::string();
  };
  std::int64_t seq = 0;
  for (const auto& p : m.dn_params) {
    if (!Binder{dnp}
             .integer(++seq)
             .text(p.id)
             .text(dn_profile)
             .text(p.name)
             .text(p.path)
             .integer(type_code_of(p.spec))
             .text(type_text_of(p.spec))
             .integer(p.spec.min)
             .integer(p.spec.max)
             .integer(p.default_value)
             .text(p.spec.unit)
             .real(p.spec.scale)
             .integer(p.comm ? 1 : 0)
             .text(p.description)
             .prov(p.prov)
             .step())
      return fail("devicenet_parameters");
    for (const auto& l : p.spec.labels)
      if (!Binder{dnpl}.text(p.id).integer(l.raw).text(l.label).prov(p.prov).step())
        return fail("devicenet_parameter_labels");
  }
  for (const auto& c : m.dn_commands) {
    if (!Binder{dnc}
             .integer(c.id)
             .text(c.id_text)
             .text(dn_profile)
             .text(c.direction)
             .text(c.name)
             .text(c.table_name)
             .text(c.range_text)
             .integer(c.spec.min)
             .integer(c.spec.max)
             .text(c.spec.unit)
             .real(c.spec.scale)
             .text(c.unit_text)
             .integer(c.addressed ? 1 : 0)
             .integer(c.direct ? 1 : 0)
             .text(c.description)
             .prov(c.prov)
             .step())
      return fail("devicenet_commands");
    for (const auto& l : c.spec.labels)
      if (!Binder{dncl}.integer(c.id).integer(l.raw).text(l.label).prov(c.prov).step())
        return fail("devicenet_command_labels");
  }
  for (auto* s : stmts) sqlite3_finalize(s);
  stmts.clear();
  if (!w.exec("COMMIT")) return fail("commit");
  if (sqlite3_close(db) != SQLITE_OK) return "closing " + path + " failed";
  return {};
}

}  // namespace

CompileReport compile_upid_db(const std::string& source_dir, const std::string& out_path) {
  CompileReport rep;
  Compiler c(rep);
  Model m;
  std::uint64_t h = fnv1a64("lmcfg-upid schema " + std::to_string(kSchemaVersion));
  std::string built_from;
  std::error_code ec;
  if (!fs::is_directory(source_dir, ec)) {
    c.error(source_dir, 0, 0, "not a directory");
    return rep;
  }
  // Unknown *.tsv files: warn, do not fail (other tables may be added later).
  std::vector<std::string> unknown;
  for (const auto& de : fs::directory_iterator(source_dir, ec)) {
    std::string n = de.path().filename().string();
    if (de.path().extension() == ".tsv" && !columns_of().count(n)) unknown.push_back(n);
  }
  std::sort(unknown.begin(), unknown.end());
  for (const auto& n : unknown)
    c.warning((fs::path(source_dir) / n).string(), 1, 1, "not a table the compiler knows; ignored");

  for (const auto& name : upid_db_source_files()) {
    std::string path = (fs::path(source_dir) / name).string();
    if (!fs::exists(path, ec)) continue;
    std::ifstream in(path, std::ios::binary);
    if (!in) {
      c.error(path, 0, 0, "cannot read the file");
      continue;
    }
    std::stringstream ss;
    ss << in.rdbuf();
    std::string content = ss.str();
    h = fnv1a64(name, h);
    h = fnv1a64(std::string_view("\0", 1), h);
    h = fnv1a64(content, h);
    h = fnv1a64(std::string_view("\0", 1), h);
    built_from += (built_from.empty() ? "" : " ") + name;
    Table t(c, path, name, std::move(content), columns_of().at(name));
    if (!t.header_ok()) continue;
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
  char hb[40];
  std::snprintf(hb, sizeof hb, "fnv1a64:%016llx", static_cast<unsigned long long>(h));
  rep.content_hash = hb;
  std::size_t nlabels = 0, ncparams = 0;
  for (const auto& p : m.params) nlabels += p.spec.labels.size();
  for (const auto& cmd : m.commands) ncparams += cmd.params.size();
  rep.counts = {{"profiles", m.profiles.size()},
                {"parameters", m.params.size()},
                {"enum_labels", nlabels},
                {"errors", m.errors.size()},
                {"motion_commands", m.commands.size()},
                {"motion_command_params", ncparams},
                {"devicenet_parameters", m.dn_params.size()},
                {"devicenet_commands", m.dn_commands.size()}};
  if (!rep.ok() || out_path.empty()) return rep;

  std::sort(m.params.begin(), m.params.end(),
            [](const Parameter& a, const Parameter& b) { return a.upid < b.upid; });
  std::string tmp = out_path + ".tmp." + std::to_string(::getpid());
  fs::remove(tmp, ec);
  std::string werr = write_db(m, tmp, rep.content_hash, built_from);
  if (werr.empty()) {
    fs::rename(tmp, out_path, ec);
    if (ec) werr = "cannot rename " + tmp + " to " + out_path + ": " + ec.message();
  }
  if (!werr.empty()) {
    fs::remove(tmp, ec);
    c.error(out_path, 0, 0, werr);
    return rep;
  }
  rep.written = true;
  return rep;
}

}  // namespace lmcfg::db
