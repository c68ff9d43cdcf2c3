#include "config/json_io.hpp"

#include <nlohmann/json.hpp>
#include <set>
#include <utility>

#include "common/layers.hpp"
#include "config/atomic_file.hpp"
#include "config/io_common.hpp"
#include "config/migrate.hpp"

namespace lmcfg::config {

using json = nlohmann::json;

TextPos text_position(std::string_view text, std::size_t offset) noexcept {
  TextPos p;
  if (offset > text.size()) offset = text.size();
  for (std::size_t i = 0; i < offset; ++i) {
    if (text[i] == '\n') {
      ++p.line;
      p.column = 1;
    } else {
      ++p.column;
    }
  }
  return p;
}

namespace {

// ---------------------------------------------------------------------------
// Locating a JSON pointer in the (already parsed, so valid) text. Only used
// on the error path, so the fast path keeps nlohmann's DOM parse.
std::size_t skip_ws(std::string_view t, std::size_t i) {
  while (i < t.size() && (t[i] == ' ' || t[i] == '\t' || t[i] == '\n' || t[i] == '\r')) ++i;
  return i;
}
std::size_t skip_string(std::string_view t, std::size_t i) {  // at '"'
  ++i;
  while (i < t.size() && t[i] != '"') i += (t[i] == '\\') ? 2 : 1;
  return i + 1;
}
std::size_t skip_value(std::string_view t, std::size_t i) {
  if (i >= t.size()) return i;
  if (t[i] == '"') return skip_string(t, i);
  if (t[i] == '{' || t[i] == '[') {
    int depth = 0;
    while (i < t.size()) {
      const char c = t[i];
      if (c == '"') {
        i = skip_string(t, i);
        continue;
      }
      if (c == '{' || c == '[') ++depth;
      if (c == '}' || c == ']') {
        if (--depth == 0) return i + 1;
      }
      ++i;
    }
    return i;
  }
  while (i < t.size() && t[i] != ',' && t[i] != '}' && t[i] != ']' && t[i] != ' ' && t[i] != '\n' &&
         t[i] != '\r' && t[i] != '\t')
    ++i;
  return i;
}

std::size_t locate(std::string_view t, const std::vector<std::string>& ptr) {
  std::size_t i = skip_ws(t, 0);
  for (const auto& tok : ptr) {
    if (i >= t.size()) return i;
    if (t[i] == '{') {
      std::size_t found = std::string::npos;
      i = skip_ws(t, i + 1);
      while (i < t.size() && t[i] == '"') {
        const std::size_t key_end = skip_string(t, i);
        std::string key;
        try {
          key = json::parse(t.substr(i, key_end - i)).get<std::string>();
        } catch (...) {
        }
        i = skip_ws(t, key_end);
        if (i < t.size() && t[i] == ':') i = skip_ws(t, i + 1);
        if (key == tok) found = i;  // the last one wins, as in the DOM
        i = skip_ws(t, skip_value(t, i));
        if (i < t.size() && t[i] == ',') i = skip_ws(t, i + 1);
      }
      if (found == std::string::npos) return i;
      i = found;
    } else if (t[i] == '[') {
      std::size_t want = 0;
      for (char c : tok) want = want * 10 + static_cast<std::size_t>(c - '0');
      i = skip_ws(t, i + 1);
      for (std::size_t k = 0; k < want && i < t.size() && t[i] != ']'; ++k) {
        i = skip_ws(t, skip_value(t, i));
        if (i < t.size() && t[i] == ',') i = skip_ws(t, i + 1);
      }
    } else {
      return i;
    }
  }
  return i;
}

std::string escape_token(const std::string& tok) {
  std::string s;
  for (char c : tok) {
    if (c == '~')
      s += "~0";
    else if (c == '/')
      s += "~1";
    else
      s += c;
  }
  return s;
}

struct Ptr {
  std::vector<std::string> tokens;
  Ptr operator/(std::string_view key) const {
    Ptr p = *this;
    p.tokens.emplace_back(key);
    return p;
  }
  Ptr operator/(std::size_t index) const {
    Ptr p = *this;
    p.tokens.push_back(std::to_string(index));
    return p;
  }
  std::string str() const {
    if (tokens.empty()) return "/";
    std::string s;
    for (const auto& t : tokens) s += "/" + escape_token(t);
    return s;
  }
};

// Index of each layer (1..4) in the document's "parameters" array.
using LayerIndex = std::array<std::size_t, lmcfg::layers::kCount>;

std::string describe(const json& j) {
  if (j.is_number()) return j.dump();
  if (j.is_string()) {
    std::string s = j.get<std::string>();
    if (s.size() > 40) s = s.substr(0, 40) + "...";
    return "string " + json(s).dump();
  }
  return std::string(j.type_name());
}

// Where a validation issue of the model is in the document.
Ptr issue_pointer(const Issue& is, const LayerIndex& layer_index) {
  Ptr p;
  switch (is.where) {
    case Issue::Where::identity:
      p = p / "identity";
      if (is.field.rfind("labels.", 0) == 0) {
        p = p / "labels" / std::string_view(is.field).substr(7);
      } else if (auto dot = is.field.find('.'); dot != std::string::npos) {
        p = p / std::string_view(is.field).substr(0, dot) /
            std::string_view(is.field).substr(dot + 1);
      } else {
        p = p / is.field;
      }
      break;
    case Issue::Where::scope:
      p = p / "scope" / is.field;
      break;
    case Issue::Where::layer:
      p = p / "parameters" / layer_index[static_cast<std::size_t>(is.layer - 1)];
      break;
    case Issue::Where::param:
      p = p / "parameters" / layer_index[static_cast<std::size_t>(is.layer - 1)] / "params" /
          is.index / is.field;
      break;
    case Issue::Where::curve:
      p = p / "curves" / is.index / is.field;
      break;
    case Issue::Where::ct_entry:
      p = p / "command_table" / is.index / is.field;
      break;
    case Issue::Where::devicenet:
      p = p / "devicenet" / is.field;
      break;
    case Issue::Where::devicenet_value:
      p = p / "devicenet" / (is.live ? "live" : "values") / is.index / is.field;
      break;
  }
  return p;
}

// ---------------------------------------------------------------------------
class Reader {
 public:
  Reader(std::string_view text, std::string_view name) : text_(text), name_(name) {}

  Error err(Errc e, const Ptr& p, const std::string& msg) const {
    return Error(e, loc(p) + ": " + msg);
  }
  std::string loc(const Ptr& p) const {
    const auto pos = text_position(text_, locate(text_, p.tokens));
    return name_ + ":" + std::to_string(pos.line) + ":" + std::to_string(pos.column) + ": " +
           p.str();
  }
  const std::string& name() const { return name_; }

  Result<void> keys(const json& obj, const Ptr& p,
                    std::initializer_list<std::string_view> allowed) const {
    for (auto it = obj.begin(); it != obj.end(); ++it) {
      bool ok = false;
      for (auto a : allowed) ok = ok || it.key() == a;
      if (!ok) {
        std::string list;
        for (auto a : allowed) list += (list.empty() ? "" : ", ") + std::string(a);
        return err(Errc::parse_error, p / it.key(), "unexpected member; expected one of: " + list);
      }
    }
    return {};
  }
  Result<const json*> member(const json& obj, const Ptr& p, std::string_view key,
                             bool required) const {
    auto it = obj.find(key);
    if (it == obj.end()) {
      if (required) return err(Errc::parse_error, p, "missing member \"" + std::string(key) + "\"");
      return static_cast<const json*>(nullptr);
    }
    return &*it;
  }
  Result<const json*> object(const json& j, const Ptr& p) const {
    if (!j.is_object())
      return err(Errc::parse_error, p, "expected an object, found " + describe(j));
    return &j;
  }
  Result<const json*> array(const json& j, const Ptr& p) const {
    if (!j.is_array()) return err(Errc::parse_error, p, "expected an array, found " + describe(j));
    return &j;
  }
  Result<std::string> string(const json& j, const Ptr& p) const {
    if (!j.is_string()) return err(Errc::parse_error, p, "expected a string, found " + describe(j));
    return j.get<std::string>();
  }
  Result<bool> boolean(const json& j, const Ptr& p) const {
    if (!j.is_boolean())
      return err(Errc::parse_error, p, "expected true or false, found " + describe(j));
    return j.get<bool>();
  }
  Result<std::uint64_t> unsigned_int(const json& j, const Ptr& p, std::uint64_t max,
                                     std::string_view what) const {
    const std::string expected =
        "expected " + std::string(what) + " (0.." + std::to_string(max) + ")";
    if (!j.is_number_integer() ||
        (j.is_number_integer() && !j.is_number_unsigned() && j.get<std::int64_t>() < 0))
      return err(Errc::parse_error, p, expected + ", found " + describe(j));
    const auto v = j.get<std::uint64_t>();
    if (v > max) return err(Errc::parse_error, p, expected + ", found " + describe(j));
    return v;
  }
  Result<std::int64_t> signed_int(const json& j, const Ptr& p, std::string_view what) const {
    if (!j.is_number_integer() ||
        (j.is_number_unsigned() && j.get<std::uint64_t>() > 0x7FFFFFFFFFFFFFFFull))
      return err(Errc::parse_error, p, "expected " + std::string(what) + ", found " + describe(j));
    return j.get<std::int64_t>();
  }
  Result<Bytes> rows(const json& j, const Ptr& p) const {
    LMCFG_TRY(array(j, p));
    Bytes out;
    for (std::size_t i = 0; i < j.size(); ++i) {
      LMCFG_ASSIGN_OR_RETURN(auto s, string(j[i], p / i));
      auto b = detail::parse_row(s);
      if (!b)
        return err(Errc::parse_error, p / i,
                   "expected 1..16 hex bytes separated by single spaces (\"46 00 03 00\"), found " +
                       describe(j[i]));
      out.insert(out.end(), b->begin(), b->end());
    }
    return out;
  }
  // Optional string member into `out`.
  Result<void> opt_string(const json& obj, const Ptr& p, std::string_view key,
                          std::string& out) const {
    LMCFG_ASSIGN_OR_RETURN(const json* m, member(obj, p, key, false));
    if (m) {
      LMCFG_ASSIGN_OR_RETURN(out, string(*m, p / key));
    }
    return {};
  }

  // The optional array member `key` of the document: each element an object
  // with only the `allowed` members, of which "decoded" (derived, not read)
  // must be an object, given to read_one(element, its pointer) in order.
  template <class F>
  Result<void> each_object(const json& doc, const char* key,
                           std::initializer_list<std::string_view> allowed, F&& read_one) const {
    const Ptr root;
    const Ptr p = root / key;
    LMCFG_ASSIGN_OR_RETURN(const json* arr, member(doc, root, key, false));
    if (!arr) return {};
    LMCFG_TRY(array(*arr, p));
    for (std::size_t i = 0; i < arr->size(); ++i) {
      const Ptr ip = p / i;
      const json& e = (*arr)[i];
      LMCFG_TRY(object(e, ip));
      LMCFG_TRY(keys(e, ip, allowed));
      LMCFG_TRY(read_one(e, ip));
      LMCFG_ASSIGN_OR_RETURN(const json* dec, member(e, ip, "decoded", false));
      if (dec) LMCFG_TRY(object(*dec, ip / "decoded"));
    }
    return {};
  }

  Result<DriveConfig> read_document(const json& doc);

 private:
  // The phases of read_v2: one member of the document each.
  Result<DriveConfig> read_v2(const json& doc, std::int64_t version);
  Result<void> read_identity(const json& idj, Identity& id) const;
  Result<void> read_scope(const json& doc, Scope& scope) const;
  Result<void> read_parameters(const json& doc, DriveConfig& cfg, LayerIndex& layer_index) const;
  Result<Parameter> read_parameter(const json& q, const Ptr& pp) const;
  Result<void> read_curves(const json& doc, std::vector<Curve>& out) const;
  Result<void> read_command_table(const json& doc, std::vector<CtEntry>& out) const;
  Result<void> read_devicenet(const json& doc, std::optional<DevicenetSection>& out) const;
  Result<void> read_devicenet_values(const json& dn, const Ptr& p, const char* key,
                                     std::vector<DevicenetValue>& out) const;
  Result<ConfigV1> read_v1(const json& doc);

  std::string_view text_;
  std::string name_;
};

Result<DriveConfig> Reader::read_document(const json& doc) {
  const Ptr root;
  LMCFG_TRY(object(doc, root));
  LMCFG_ASSIGN_OR_RETURN(const json* fmt, member(doc, root, "format", true));
  LMCFG_ASSIGN_OR_RETURN(auto fmt_s, string(*fmt, root / "format"));
  LMCFG_TRY(detail::check_format_id(fmt_s, loc(root / "format")));
  LMCFG_ASSIGN_OR_RETURN(const json* ver, member(doc, root, "format_version", true));
  LMCFG_ASSIGN_OR_RETURN(auto version,
                         signed_int(*ver, root / "format_version", "an integer format version"));
  LMCFG_TRY(detail::check_format_version(version, name_, loc(root / "format_version")));
  if (version == 1) {
    LMCFG_ASSIGN_OR_RETURN(auto v1, read_v1(doc));
    return migrate_v1_to_v2(v1);
  }
  return read_v2(doc, version);
}

// Versions 2 and 3: a version 2 file is a version 3 file without `devicenet`.
Result<DriveConfig> Reader::read_v2(const json& doc, std::int64_t version) {
  const Ptr root;
  if (version < 3 && doc.contains("devicenet"))
    return err(Errc::parse_error, root / "devicenet",
               "unexpected member; the devicenet section is new in format_version 3, this file "
               "says " +
                   std::to_string(version));
  LMCFG_TRY(keys(doc, root,
                 {"format", "format_version", "identity", "scope", "parameters", "curves",
                  "command_table", "devicenet"}));
  DriveConfig cfg;
  LMCFG_ASSIGN_OR_RETURN(const json* idj, member(doc, root, "identity", false));
  if (idj) LMCFG_TRY(read_identity(*idj, cfg.identity));
  LMCFG_TRY(read_scope(doc, cfg.scope));
  LayerIndex layer_index{};
  LMCFG_TRY(read_parameters(doc, cfg, layer_index));
  LMCFG_TRY(read_curves(doc, cfg.curves));
  LMCFG_TRY(read_command_table(doc, cfg.ct_entries));
  LMCFG_TRY(read_devicenet(doc, cfg.devicenet));
  if (auto is = find_issue(cfg))
    return err(Errc::validation_failed, issue_pointer(*is, layer_index), is->message);
  canonicalize(cfg);
  return cfg;
}

// identity (optional; every member optional)
Result<void> Reader::read_identity(const json& idj, Identity& id) const {
  const Ptr p = Ptr{} / "identity";
  LMCFG_TRY(object(idj, p));
  LMCFG_TRY(keys(idj, p,
                 {"macid", "link", "product", "firmware", "upid_fingerprint", "tool_version",
                  "upid_db", "captured_at", "labels"}));
  LMCFG_TRY(opt_string(idj, p, "macid", id.macid));
  LMCFG_TRY(opt_string(idj, p, "product", id.product));
  LMCFG_TRY(opt_string(idj, p, "firmware", id.firmware));
  LMCFG_TRY(opt_string(idj, p, "upid_fingerprint", id.upid_fingerprint));
  LMCFG_TRY(opt_string(idj, p, "tool_version", id.tool_version));
  LMCFG_TRY(opt_string(idj, p, "captured_at", id.captured_at));
  LMCFG_ASSIGN_OR_RETURN(const json* link, member(idj, p, "link", false));
  if (link) {
    const Ptr lp = p / "link";
    LMCFG_TRY(object(*link, lp));
    LMCFG_TRY(keys(*link, lp, {"port", "baud", "parity", "stop_bits", "checksum"}));
    LMCFG_TRY(opt_string(*link, lp, "port", id.link.port));
    LMCFG_TRY(opt_string(*link, lp, "baud", id.link.baud));
    LMCFG_TRY(opt_string(*link, lp, "parity", id.link.parity));
    LMCFG_TRY(opt_string(*link, lp, "stop_bits", id.link.stop_bits));
    LMCFG_TRY(opt_string(*link, lp, "checksum", id.link.checksum));
  }
  LMCFG_ASSIGN_OR_RETURN(const json* db, member(idj, p, "upid_db", false));
  if (db) {
    const Ptr dp = p / "upid_db";
    LMCFG_TRY(object(*db, dp));
    LMCFG_TRY(keys(*db, dp, {"version", "hash"}));
    LMCFG_TRY(opt_string(*db, dp, "version", id.upid_db_version));
    LMCFG_TRY(opt_string(*db, dp, "hash", id.upid_db_hash));
  }
  LMCFG_ASSIGN_OR_RETURN(const json* labels, member(idj, p, "labels", false));
  if (labels) {
    const Ptr lp = p / "labels";
    LMCFG_TRY(object(*labels, lp));
    for (auto it = labels->begin(); it != labels->end(); ++it) {
      LMCFG_ASSIGN_OR_RETURN(auto v, string(it.value(), lp / it.key()));
      id.labels[it.key()] = std::move(v);
    }
  }
  return {};
}

// scope (required)
Result<void> Reader::read_scope(const json& doc, Scope& scope) const {
  const Ptr root;
  const Ptr p = root / "scope";
  LMCFG_ASSIGN_OR_RETURN(const json* sj, member(doc, root, "scope", true));
  LMCFG_TRY(object(*sj, p));
  LMCFG_TRY(keys(*sj, p, {"layers", "parameters", "curves", "command_table"}));
  LMCFG_ASSIGN_OR_RETURN(const json* lj, member(*sj, p, "layers", true));
  LMCFG_TRY(array(*lj, p / "layers"));
  scope.layers = {false, false, false, false};
  for (std::size_t i = 0; i < lj->size(); ++i) {
    const Ptr ip = p / "layers" / i;
    if (!(*lj)[i].is_number_unsigned() || (*lj)[i].get<std::uint64_t>() < 1 ||
        (*lj)[i].get<std::uint64_t>() > 4)
      return err(Errc::parse_error, ip,
                 "expected a layer number 1..4, found " + describe((*lj)[i]));
    const auto l = (*lj)[i].get<std::size_t>();
    if (scope.layers[l - 1])
      return err(Errc::validation_failed, ip, "layer " + std::to_string(l) + " listed twice");
    scope.layers[l - 1] = true;
  }
  LMCFG_ASSIGN_OR_RETURN(const json* pj, member(*sj, p, "parameters", true));
  LMCFG_ASSIGN_OR_RETURN(auto ps, string(*pj, p / "parameters"));
  auto set = param_set_from_string(ps);
  if (!set)
    return err(Errc::parse_error, p / "parameters",
               "expected \"modified\" or \"full\", found " + describe(*pj));
  scope.parameters = *set;
  LMCFG_ASSIGN_OR_RETURN(const json* cj, member(*sj, p, "curves", true));
  LMCFG_ASSIGN_OR_RETURN(scope.curves, boolean(*cj, p / "curves"));
  LMCFG_ASSIGN_OR_RETURN(const json* tj, member(*sj, p, "command_table", true));
  LMCFG_ASSIGN_OR_RETURN(scope.command_table, boolean(*tj, p / "command_table"));
  return {};
}

// parameters (required); layer_index: where each layer is in the array
Result<void> Reader::read_parameters(const json& doc, DriveConfig& cfg,
                                     LayerIndex& layer_index) const {
  const Ptr root;
  const Ptr p = root / "parameters";
  LMCFG_ASSIGN_OR_RETURN(const json* pj, member(doc, root, "parameters", true));
  LMCFG_TRY(array(*pj, p));
  std::array<bool, lmcfg::layers::kCount> seen{};
  for (std::size_t li = 0; li < pj->size(); ++li) {
    const Ptr lp = p / li;
    const json& lj = (*pj)[li];
    LMCFG_TRY(object(lj, lp));
    LMCFG_TRY(keys(lj, lp, {"layer", "name", "params"}));
    LMCFG_ASSIGN_OR_RETURN(const json* nj, member(lj, lp, "layer", true));
    LMCFG_ASSIGN_OR_RETURN(auto l, unsigned_int(*nj, lp / "layer", 4, "a layer number"));
    if (l < 1)
      return err(Errc::parse_error, lp / "layer", "expected a layer number (1..4), found 0");
    if (seen[l - 1])
      return err(Errc::validation_failed, lp / "layer",
                 "layer " + std::to_string(l) + " appears twice");
    seen[l - 1] = true;
    layer_index[l - 1] = li;
    std::string ignored_name;
    LMCFG_TRY(opt_string(lj, lp, "name", ignored_name));
    LMCFG_ASSIGN_OR_RETURN(const json* arr, member(lj, lp, "params", true));
    LMCFG_TRY(array(*arr, lp / "params"));
    auto& out = cfg.layer(static_cast<int>(l));
    out.reserve(arr->size());
    for (std::size_t i = 0; i < arr->size(); ++i) {
      const Ptr pp = lp / "params" / i;
      const json& q = (*arr)[i];
      LMCFG_TRY(object(q, pp));
      LMCFG_TRY(keys(q, pp, {"upid", "value", "type", "default", "name", "unit", "scaled"}));
      LMCFG_ASSIGN_OR_RETURN(Parameter prm, read_parameter(q, pp));
      out.push_back(std::move(prm));
    }
  }
  return {};
}

// One parameter of a layer's "params".
Result<Parameter> Reader::read_parameter(const json& q, const Ptr& pp) const {
  Parameter prm;
  LMCFG_ASSIGN_OR_RETURN(const json* uj, member(q, pp, "upid", true));
  LMCFG_ASSIGN_OR_RETURN(auto us, string(*uj, pp / "upid"));
  auto upid = detail::parse_upid_hex(us);
  if (!upid)
    return err(Errc::parse_error, pp / "upid",
               "expected a UPID as 4 hex digits (\"13A2\"), found " + describe(*uj));
  prm.upid = *upid;
  LMCFG_ASSIGN_OR_RETURN(const json* vj, member(q, pp, "value", true));
  LMCFG_ASSIGN_OR_RETURN(auto v,
                         unsigned_int(*vj, pp / "value", 0xFFFFFFFFu, "an unsigned 32-bit value"));
  prm.value = static_cast<std::uint32_t>(v);
  LMCFG_ASSIGN_OR_RETURN(const json* tj, member(q, pp, "type", false));
  if (tj) {
    LMCFG_ASSIGN_OR_RETURN(auto t, unsigned_int(*tj, pp / "type", 15, "a type code"));
    prm.type = static_cast<std::uint8_t>(t);
  }
  LMCFG_ASSIGN_OR_RETURN(const json* dj, member(q, pp, "default", false));
  if (dj) {
    LMCFG_ASSIGN_OR_RETURN(
        auto d, unsigned_int(*dj, pp / "default", 0xFFFFFFFFu, "an unsigned 32-bit value"));
    prm.default_value = static_cast<std::uint32_t>(d);
  }
  LMCFG_TRY(opt_string(q, pp, "name", prm.name));
  LMCFG_TRY(opt_string(q, pp, "unit", prm.unit));
  LMCFG_TRY(opt_string(q, pp, "scaled", prm.scaled));
  return prm;
}

// curves (optional)
Result<void> Reader::read_curves(const json& doc, std::vector<Curve>& out) const {
  return each_object(doc, "curves", {"id", "info", "data", "decoded"},
                     [&](const json& c, const Ptr& cp) -> Result<void> {
                       Curve curve;
                       LMCFG_ASSIGN_OR_RETURN(const json* ij, member(c, cp, "id", true));
                       LMCFG_ASSIGN_OR_RETURN(auto id,
                                              unsigned_int(*ij, cp / "id", 0xFFFF, "a curve ID"));
                       curve.id = static_cast<std::uint32_t>(id);
                       LMCFG_ASSIGN_OR_RETURN(const json* inf, member(c, cp, "info", true));
                       LMCFG_ASSIGN_OR_RETURN(curve.info, rows(*inf, cp / "info"));
                       LMCFG_ASSIGN_OR_RETURN(const json* dat, member(c, cp, "data", true));
                       LMCFG_ASSIGN_OR_RETURN(curve.data, rows(*dat, cp / "data"));
                       out.push_back(std::move(curve));
                       return {};
                     });
}

// command table (optional)
Result<void> Reader::read_command_table(const json& doc, std::vector<CtEntry>& out) const {
  return each_object(doc, "command_table", {"id", "raw", "decoded"},
                     [&](const json& e, const Ptr& ep) -> Result<void> {
                       CtEntry entry;
                       LMCFG_ASSIGN_OR_RETURN(const json* ij, member(e, ep, "id", true));
                       LMCFG_ASSIGN_OR_RETURN(
                           auto id, unsigned_int(*ij, ep / "id", 0xFFFFFFFFu, "an entry ID"));
                       entry.id = static_cast<std::uint32_t>(id);
                       LMCFG_ASSIGN_OR_RETURN(const json* rj, member(e, ep, "raw", true));
                       LMCFG_ASSIGN_OR_RETURN(entry.raw, rows(*rj, ep / "raw"));
                       out.push_back(std::move(entry));
                       return {};
                     });
}

// devicenet (optional, format_version 3)
Result<void> Reader::read_devicenet(const json& doc, std::optional<DevicenetSection>& out) const {
  const Ptr root;
  const Ptr p = root / "devicenet";
  LMCFG_ASSIGN_OR_RETURN(const json* dj, member(doc, root, "devicenet", false));
  if (!dj) return {};
  LMCFG_TRY(object(*dj, p));
  LMCFG_TRY(keys(*dj, p, {"can_bitrate", "io_modules", "motors", "values", "live"}));
  DevicenetSection dn;
  LMCFG_ASSIGN_OR_RETURN(const json* bj, member(*dj, p, "can_bitrate", true));
  LMCFG_ASSIGN_OR_RETURN(auto rate,
                         unsigned_int(*bj, p / "can_bitrate", 0xFFFFFFFFu, "a CAN bit rate"));
  dn.can_bitrate = static_cast<std::uint32_t>(rate);
  LMCFG_ASSIGN_OR_RETURN(const json* ij, member(*dj, p, "io_modules", false));
  if (ij) {
    LMCFG_TRY(array(*ij, p / "io_modules"));
    for (std::size_t i = 0; i < ij->size(); ++i) {
      LMCFG_ASSIGN_OR_RETURN(auto m, string((*ij)[i], p / "io_modules" / i));
      dn.io_modules.push_back(std::move(m));
    }
  }
  LMCFG_ASSIGN_OR_RETURN(const json* mj, member(*dj, p, "motors", true));
  LMCFG_TRY(array(*mj, p / "motors"));
  for (std::size_t i = 0; i < mj->size(); ++i) {
    const json& m = (*mj)[i];
    const auto motor =
        m.is_string() ? detail::parse_motor_letter(m.get<std::string>()) : std::nullopt;
    if (!motor)
      return err(Errc::parse_error, p / "motors" / i,
                 "expected a motor \"A\"..\"D\", found " + describe(m));
    dn.motors.push_back(*motor);
  }
  LMCFG_TRY(read_devicenet_values(*dj, p, "values", dn.values));
  LMCFG_TRY(read_devicenet_values(*dj, p, "live", dn.live));
  out = std::move(dn);
  return {};
}

// devicenet/values or devicenet/live (optional)
Result<void> Reader::read_devicenet_values(const json& dn, const Ptr& p, const char* key,
                                           std::vector<DevicenetValue>& out) const {
  LMCFG_ASSIGN_OR_RETURN(const json* arr, member(dn, p, key, false));
  if (!arr) return {};
  LMCFG_TRY(array(*arr, p / key));
  for (std::size_t i = 0; i < arr->size(); ++i) {
    const Ptr vp = p / key / i;
    const json& vj = (*arr)[i];
    LMCFG_TRY(object(vj, vp));
    LMCFG_TRY(keys(vj, vp, {"motor", "command", "raw", "name", "scaled", "unit"}));
    DevicenetValue v;
    LMCFG_ASSIGN_OR_RETURN(const json* mj, member(vj, vp, "motor", true));
    const auto motor =
        mj->is_string() ? detail::parse_devicenet_motor(mj->get<std::string>()) : std::nullopt;
    if (!motor)
      return err(Errc::parse_error, vp / "motor",
                 "expected \"controller\" or a motor \"A\"..\"D\", found " + describe(*mj));
    v.motor = *motor;
    LMCFG_ASSIGN_OR_RETURN(const json* cj, member(vj, vp, "command", true));
    const auto command =
        cj->is_string() ? detail::parse_command_hex(cj->get<std::string>()) : std::nullopt;
    if (!command)
      return err(Errc::parse_error, vp / "command",
                 "expected a command ID as 2 hex digits (\"34\"), found " + describe(*cj));
    v.command = *command;
    LMCFG_ASSIGN_OR_RETURN(const json* rj, member(vj, vp, "raw", true));
    LMCFG_ASSIGN_OR_RETURN(auto raw, unsigned_int(*rj, vp / "raw", 0xFFFF, "a 16-bit word"));
    v.raw = static_cast<std::uint16_t>(raw);
    LMCFG_TRY(opt_string(vj, vp, "name", v.name));
    LMCFG_TRY(opt_string(vj, vp, "scaled", v.scaled));
    LMCFG_TRY(opt_string(vj, vp, "unit", v.unit));
    out.push_back(std::move(v));
  }
  return {};
}

Result<ConfigV1> Reader::read_v1(const json& doc) {
  const Ptr root;
  LMCFG_TRY(keys(doc, root,
                 {"format", "format_version", "drive", "parameters", "curves", "command_table"}));
  ConfigV1 v1;
  v1.field_sep = "/";
  LMCFG_ASSIGN_OR_RETURN(const json* dj, member(doc, root, "drive", false));
  if (dj) {
    const Ptr p = root / "drive";
    LMCFG_TRY(object(*dj, p));
    LMCFG_TRY(keys(*dj, p,
                   {"macid", "port", "baud", "parity", "stop_bits", "checksum", "tool_version",
                    "captured_at"}));
    LMCFG_TRY(opt_string(*dj, p, "macid", v1.macid));
    LMCFG_TRY(opt_string(*dj, p, "port", v1.port));
    LMCFG_TRY(opt_string(*dj, p, "parity", v1.parity));
    LMCFG_TRY(opt_string(*dj, p, "stop_bits", v1.stop_bits));
    LMCFG_TRY(opt_string(*dj, p, "checksum", v1.checksum));
    LMCFG_TRY(opt_string(*dj, p, "tool_version", v1.tool_version));
    LMCFG_TRY(opt_string(*dj, p, "captured_at", v1.captured_at));
    LMCFG_ASSIGN_OR_RETURN(const json* bj, member(*dj, p, "baud", false));
    if (bj) {
      LMCFG_ASSIGN_OR_RETURN(auto baud, unsigned_int(*bj, p / "baud", 0xFFFFFFFFu, "a baud rate"));
      v1.baud = std::to_string(baud);
    }
  }
  LMCFG_ASSIGN_OR_RETURN(const json* pj, member(doc, root, "parameters", true));
  LMCFG_TRY(array(*pj, root / "parameters"));
  for (std::size_t i = 0; i < pj->size(); ++i) {
    const Ptr pp = root / "parameters" / i;
    const json& q = (*pj)[i];
    LMCFG_TRY(object(q, pp));
    LMCFG_TRY(keys(q, pp, {"upid", "value"}));
    ConfigV1::Param prm;
    LMCFG_ASSIGN_OR_RETURN(const json* uj, member(q, pp, "upid", true));
    LMCFG_ASSIGN_OR_RETURN(prm.upid, signed_int(*uj, pp / "upid", "a decimal UPID"));
    LMCFG_ASSIGN_OR_RETURN(const json* vj, member(q, pp, "value", true));
    LMCFG_ASSIGN_OR_RETURN(prm.value, signed_int(*vj, pp / "value", "a decimal value"));
    prm.where = loc(pp);
    v1.params.push_back(std::move(prm));
  }
  auto blocks = [&](std::string_view key, bool curve,
                    std::vector<ConfigV1::Block>& out) -> Result<void> {
    LMCFG_ASSIGN_OR_RETURN(const json* aj, member(doc, root, key, false));
    if (!aj) return {};
    const Ptr p = root / key;
    LMCFG_TRY(array(*aj, p));
    for (std::size_t i = 0; i < aj->size(); ++i) {
      const Ptr bp = p / i;
      const json& b = (*aj)[i];
      LMCFG_TRY(object(b, bp));
      if (curve) {
        LMCFG_TRY(keys(b, bp, {"id", "info", "data"}));
      } else {
        LMCFG_TRY(keys(b, bp, {"id", "data"}));
      }
      ConfigV1::Block blk;
      LMCFG_ASSIGN_OR_RETURN(const json* ij, member(b, bp, "id", true));
      LMCFG_ASSIGN_OR_RETURN(blk.id, signed_int(*ij, bp / "id", "a decimal ID"));
      for (std::string_view field : {std::string_view("info"), std::string_view("data")}) {
        if (field == "info" && !curve) continue;
        LMCFG_ASSIGN_OR_RETURN(const json* hj, member(b, bp, field, true));
        LMCFG_ASSIGN_OR_RETURN(auto hs, string(*hj, bp / field));
        auto bytes = from_hex(hs);
        if (!bytes)
          return err(Errc::parse_error, bp / field, "expected hex bytes (\"46 00 03 00\")");
        (field == "info" ? blk.info : blk.data) = std::move(*bytes);
      }
      blk.where = loc(bp);
      out.push_back(std::move(blk));
    }
    return {};
  };
  LMCFG_TRY(blocks("curves", true, v1.curves));
  LMCFG_TRY(blocks("command_table", false, v1.ct_entries));
  return v1;
}

}  // namespace

Result<DriveConfig> read_json(std::string_view text, std::string_view name) {
  json doc;
  try {
    doc = json::parse(text.begin(), text.end());
  } catch (const json::parse_error& e) {
    std::string what = e.what();
    // "[json.exception.parse_error.101] parse error at line 1, column 5: syntax error ..."
    if (auto col = what.find("column "); col != std::string::npos) {
      if (auto colon = what.find(": ", col); colon != std::string::npos)
        what = what.substr(colon + 2);
    }
    const std::size_t off = e.byte == 0 ? 0 : e.byte - 1;
    const auto pos = text_position(text, off);
    return Error(Errc::parse_error, std::string(name) + ":" + std::to_string(pos.line) + ":" +
                                        std::to_string(pos.column) + ": " + what);
  } catch (const json::out_of_range& e) {
    // A number no double can hold (found by fuzz_json_config): nlohmann names
    // the token but not its place, so locate the token's first occurrence.
    std::string what = e.what();
    std::string token;
    if (auto q = what.find('\''); q != std::string::npos) {
      if (auto q2 = what.find('\'', q + 1); q2 != std::string::npos)
        token = what.substr(q + 1, q2 - q - 1);
    }
    const auto at = token.empty() ? std::string_view::npos : text.find(token);
    const auto pos = text_position(text, at == std::string_view::npos ? 0 : at);
    std::string shown = token.size() > 24 ? token.substr(0, 24) + "..." : token;
    return Error(Errc::parse_error, std::string(name) + ":" + std::to_string(pos.line) + ":" +
                                        std::to_string(pos.column) + ": number " + shown +
                                        " is out of range (expected an integer value field)");
  }
  Reader r(text, name);
  return r.read_document(doc);
}

Result<DriveConfig> read_json_file(const std::filesystem::path& path) {
  LMCFG_ASSIGN_OR_RETURN(auto text, read_text_file(path));
  return read_json(text, path.string());
}

}  // namespace lmcfg::config
