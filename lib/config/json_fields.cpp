// The JSON reader's located checks and the field walkers' per-kind code
// (json_fields.hpp).
#include "config/json_fields.hpp"

#include "config/io_common.hpp"
#include "config/json_io.hpp"  // text_position

namespace lmcfg::config::detail {

using fields::Kind;
using fields::Use;

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

}  // namespace

Ptr Ptr::operator/(std::string_view key) const {
  Ptr p = *this;
  p.tokens.emplace_back(key);
  return p;
}
Ptr Ptr::operator/(std::size_t index) const {
  Ptr p = *this;
  p.tokens.push_back(std::to_string(index));
  return p;
}
std::string Ptr::str() const {
  if (tokens.empty()) return "/";
  std::string s;
  for (const auto& t : tokens) s += "/" + escape_token(t);
  return s;
}

std::string describe(const json& j) {
  if (j.is_number()) return j.dump();
  if (j.is_string()) {
    std::string s = j.get<std::string>();
    if (s.size() > 40) {
      // Cut at a character boundary: the parser accepted valid UTF-8, and
      // half a multi-byte character would not dump.
      std::size_t n = 40;
      while (n > 0 && (static_cast<unsigned char>(s[n]) & 0xC0) == 0x80) --n;
      s = s.substr(0, n) + "...";
    }
    return "string " + json(s).dump(-1, ' ', false, json::error_handler_t::replace);
  }
  return std::string(j.type_name());
}

Error JsonReader::err(Errc e, const Ptr& p, const std::string& msg) const {
  return Error(e, loc(p) + ": " + msg);
}

std::string JsonReader::loc(const Ptr& p) const {
  const auto pos = text_position(text_, locate(text_, p.tokens));
  return name_ + ":" + std::to_string(pos.line) + ":" + std::to_string(pos.column) + ": " + p.str();
}

Result<void> JsonReader::keys(const json& obj, const Ptr& p,
                              std::span<const std::string_view> allowed) const {
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

Result<const json*> JsonReader::member(const json& obj, const Ptr& p, std::string_view key,
                                       bool required) const {
  auto it = obj.find(key);
  if (it == obj.end()) {
    if (required) return err(Errc::parse_error, p, "missing member \"" + std::string(key) + "\"");
    return static_cast<const json*>(nullptr);
  }
  return &*it;
}

Result<const json*> JsonReader::object(const json& j, const Ptr& p) const {
  if (!j.is_object()) return err(Errc::parse_error, p, "expected an object, found " + describe(j));
  return &j;
}

Result<const json*> JsonReader::array(const json& j, const Ptr& p) const {
  if (!j.is_array()) return err(Errc::parse_error, p, "expected an array, found " + describe(j));
  return &j;
}

Result<std::string> JsonReader::string(const json& j, const Ptr& p) const {
  if (!j.is_string()) return err(Errc::parse_error, p, "expected a string, found " + describe(j));
  return j.get<std::string>();
}

Result<bool> JsonReader::boolean(const json& j, const Ptr& p) const {
  if (!j.is_boolean())
    return err(Errc::parse_error, p, "expected true or false, found " + describe(j));
  return j.get<bool>();
}

Result<std::uint64_t> JsonReader::unsigned_int(const json& j, const Ptr& p, std::uint64_t max,
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

Result<std::int64_t> JsonReader::signed_int(const json& j, const Ptr& p,
                                            std::string_view what) const {
  if (!j.is_number_integer() ||
      (j.is_number_unsigned() && j.get<std::uint64_t>() > 0x7FFFFFFFFFFFFFFFull))
    return err(Errc::parse_error, p, "expected " + std::string(what) + ", found " + describe(j));
  return j.get<std::int64_t>();
}

Result<Bytes> JsonReader::rows(const json& j, const Ptr& p) const {
  LMCFG_TRY(array(j, p));
  Bytes out;
  for (std::size_t i = 0; i < j.size(); ++i) {
    LMCFG_ASSIGN_OR_RETURN(auto s, string(j[i], p / i));
    auto b = parse_row(s);
    if (!b)
      return err(Errc::parse_error, p / i,
                 "expected 1..16 hex bytes separated by single spaces (\"46 00 03 00\"), found " +
                     describe(j[i]));
    out.insert(out.end(), b->begin(), b->end());
  }
  return out;
}

Result<void> JsonReader::opt_string(const json& obj, const Ptr& p, std::string_view key,
                                    std::string& out) const {
  LMCFG_ASSIGN_OR_RETURN(const json* m, member(obj, p, key, false));
  if (m) {
    LMCFG_ASSIGN_OR_RETURN(out, string(*m, p / key));
  }
  return {};
}

Result<void> JsonReader::since(const json& obj, const Ptr& p, const fields::Spec& s) const {
  if (version_ >= s.since || !obj.contains(s.key)) return {};
  return err(Errc::parse_error, p / s.key,
             "unexpected member; the " + std::string(s.key) + " field is new in format_version " +
                 std::to_string(s.since) + ", this file says " + std::to_string(version_));
}

Result<void> JsonReader::read_value(const json& obj, const Ptr& rp, const fields::Spec& s,
                                    const fields::Ref& ref) const {
  LMCFG_ASSIGN_OR_RETURN(const json* m, member(obj, rp, s.key, s.use == Use::required));
  if (!m) return {};
  const json& j = *m;
  const Ptr p = rp / s.key;
  switch (s.kind) {
    case Kind::text: {
      LMCFG_ASSIGN_OR_RETURN(*std::get<std::string*>(ref), string(j, p));
      return {};
    }
    case Kind::upid: {
      LMCFG_ASSIGN_OR_RETURN(auto text, string(j, p));
      const auto upid = parse_upid_hex(text);
      if (!upid)
        return err(Errc::parse_error, p,
                   "expected a UPID as 4 hex digits (\"13A2\"), found " + describe(j));
      *std::get<std::uint16_t*>(ref) = *upid;
      return {};
    }
    case Kind::number: {
      LMCFG_ASSIGN_OR_RETURN(auto v, unsigned_int(j, p, s.max, s.what));
      fields::set_number(ref, v);
      return {};
    }
    case Kind::flag: {
      LMCFG_ASSIGN_OR_RETURN(*std::get<bool*>(ref), boolean(j, p));
      return {};
    }
    case Kind::rows: {
      LMCFG_ASSIGN_OR_RETURN(*std::get<Bytes*>(ref), rows(j, p));
      return {};
    }
    case Kind::motor: {
      const auto motor = j.is_string() ? parse_devicenet_motor(j.get<std::string>()) : std::nullopt;
      if (!motor)
        return err(Errc::parse_error, p,
                   "expected \"controller\" or a motor \"A\"..\"D\", found " + describe(j));
      *std::get<int*>(ref) = *motor;
      return {};
    }
    case Kind::command: {
      const auto command = j.is_string() ? parse_command_hex(j.get<std::string>()) : std::nullopt;
      if (!command)
        return err(Errc::parse_error, p,
                   "expected a command ID as 2 hex digits (\"34\"), found " + describe(j));
      *std::get<std::uint8_t*>(ref) = *command;
      return {};
    }
    case Kind::param_set: {
      LMCFG_ASSIGN_OR_RETURN(auto text, string(j, p));
      const auto set = param_set_from_string(text);
      if (!set)
        return err(Errc::parse_error, p, "expected \"modified\" or \"full\", found " + describe(j));
      *std::get<ParamSet*>(ref) = *set;
      return {};
    }
    case Kind::group:  // read_fields reads groups
      return {};
    default:
      return read_list(j, p, s, ref);
  }
}

// The kinds that hold several values.
Result<void> JsonReader::read_list(const json& j, const Ptr& p, const fields::Spec& s,
                                   const fields::Ref& ref) const {
  if (s.kind == Kind::label_map) {
    LMCFG_TRY(object(j, p));
    auto& out = *std::get<std::map<std::string, std::string>*>(ref);
    for (auto it = j.begin(); it != j.end(); ++it) {
      LMCFG_ASSIGN_OR_RETURN(auto v, string(it.value(), p / it.key()));
      out[it.key()] = std::move(v);
    }
    return {};
  }
  LMCFG_TRY(array(j, p));
  if (s.kind == Kind::layer_set) *std::get<std::array<bool, lmcfg::layers::kCount>*>(ref) = {};
  for (std::size_t i = 0; i < j.size(); ++i) {
    const Ptr ip = p / i;
    const json& e = j[i];
    if (s.kind == Kind::layer_set) {
      auto& layers = *std::get<std::array<bool, lmcfg::layers::kCount>*>(ref);
      if (!e.is_number_unsigned() || e.get<std::uint64_t>() < 1 || e.get<std::uint64_t>() > 4)
        return err(Errc::parse_error, ip, "expected a layer number 1..4, found " + describe(e));
      const auto l = e.get<std::size_t>();
      if (layers[l - 1])
        return err(Errc::validation_failed, ip, "layer " + std::to_string(l) + " listed twice");
      layers[l - 1] = true;
    } else if (s.kind == Kind::motor_list) {
      const auto motor = e.is_string() ? parse_motor_letter(e.get<std::string>()) : std::nullopt;
      if (!motor)
        return err(Errc::parse_error, ip, "expected a motor \"A\"..\"D\", found " + describe(e));
      std::get<std::vector<int>*>(ref)->push_back(*motor);
    } else if (s.kind == Kind::text_list) {
      LMCFG_ASSIGN_OR_RETURN(auto text, string(e, ip));
      std::get<std::vector<std::string>*>(ref)->push_back(std::move(text));
    } else {  // value_list
      DevicenetValue v;
      LMCFG_TRY(read_record(e, ip, fields::devicenet_value_fields(), v));
      std::get<std::vector<DevicenetValue>*>(ref)->push_back(std::move(v));
    }
  }
  return {};
}

void write_value(ojson& out, const fields::Spec& s, const fields::Ref& ref) {
  const std::string key(s.key);
  switch (s.kind) {
    case Kind::text: {
      const auto& v = *std::get<std::string*>(ref);
      if (s.use != Use::nonempty || !v.empty()) out[key] = v;
      return;
    }
    case Kind::upid:
      out[key] = upid_hex(*std::get<std::uint16_t*>(ref));
      return;
    case Kind::number:
      if (auto v = fields::number_of(ref)) out[key] = *v;
      return;
    case Kind::flag:
      out[key] = *std::get<bool*>(ref);
      return;
    case Kind::rows: {
      ojson a = ojson::array();
      for (auto& r : block_rows(*std::get<Bytes*>(ref))) a.push_back(std::move(r));
      out[key] = std::move(a);
      return;
    }
    case Kind::motor:
      out[key] = devicenet_motor_text(*std::get<int*>(ref));
      return;
    case Kind::command:
      out[key] = command_hex(*std::get<std::uint8_t*>(ref));
      return;
    case Kind::param_set:
      out[key] = std::string(to_string(*std::get<ParamSet*>(ref)));
      return;
    case Kind::layer_set: {
      ojson a = ojson::array();
      const auto& layers = *std::get<std::array<bool, lmcfg::layers::kCount>*>(ref);
      for (int l = 1; l <= lmcfg::layers::kCount; ++l)
        if (layers[static_cast<std::size_t>(l - 1)]) a.push_back(l);
      out[key] = std::move(a);
      return;
    }
    case Kind::motor_list: {
      ojson a = ojson::array();
      for (int m : *std::get<std::vector<int>*>(ref)) a.push_back(devicenet_motor_text(m));
      out[key] = std::move(a);
      return;
    }
    case Kind::text_list: {
      const auto& list = *std::get<std::vector<std::string>*>(ref);
      if (s.use != Use::nonempty || !list.empty()) out[key] = list;
      return;
    }
    case Kind::label_map: {
      ojson o = ojson::object();
      for (const auto& [k, v] : *std::get<std::map<std::string, std::string>*>(ref)) o[k] = v;
      out[key] = std::move(o);
      return;
    }
    case Kind::value_list: {
      ojson a = ojson::array();
      for (const auto& v : *std::get<std::vector<DevicenetValue>*>(ref))
        a.push_back(write_record(fields::devicenet_value_fields(), v));
      out[key] = std::move(a);
      return;
    }
    case Kind::group:  // write_record writes groups
      return;
  }
}

}  // namespace lmcfg::config::detail
