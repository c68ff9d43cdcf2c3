// The XML reader's located checks and the field walkers' per-kind code
// (xml_fields.hpp).
#include "config/xml_fields.hpp"

#include <sstream>

#include "config/io_common.hpp"

namespace lmcfg::config::detail {

using fields::Kind;
using fields::Use;

namespace {

bool blank(const char* s) {
  for (; *s; ++s)
    if (*s != ' ' && *s != '\t' && *s != '\n' && *s != '\r') return false;
  return true;
}

bool is_repeated(std::string_view name) {
  return name == "layer" || name == "param" || name == "curve" || name == "entry" ||
         name == "row" || name == "label" || name == "setpoint" || name == "module" ||
         name == "value";
}

}  // namespace

std::string node_path(xml_node n) {
  std::string path;
  for (; n && n.type() == pugi::node_element; n = n.parent()) {
    std::string seg = "/" + std::string(n.name());
    if (is_repeated(n.name())) {
      std::size_t k = 1;
      for (xml_node s = n.previous_sibling(n.name()); s; s = s.previous_sibling(n.name())) ++k;
      seg += "[" + std::to_string(k) + "]";
    }
    path = seg + path;
  }
  return path.empty() ? "/" : path;
}

Error XmlReader::err(Errc e, xml_node n, const std::string& msg) const {
  return Error(e, name_ + ": " + node_path(n) + ": " + msg);
}

Error XmlReader::err_attr(Errc e, xml_node n, std::string_view attr, const std::string& msg) const {
  return Error(e, name_ + ": " + node_path(n) + "/@" + std::string(attr) + ": " + msg);
}

Result<void> XmlReader::shape(xml_node n, std::span<const std::string_view> attrs,
                              std::span<const std::string_view> children) const {
  for (auto a : n.attributes()) {
    bool ok = false;
    for (auto x : attrs) ok = ok || x == a.name();
    if (!ok) {
      std::string list;
      for (auto x : attrs) list += (list.empty() ? "" : ", ") + std::string(x);
      return err_attr(
          Errc::parse_error, n, a.name(),
          "unexpected attribute; expected " + (list.empty() ? "none" : "one of: " + list));
    }
  }
  for (auto c : n.children()) {
    if (c.type() == pugi::node_pcdata || c.type() == pugi::node_cdata) {
      if (!blank(c.value()))
        return err(Errc::parse_error, n, "unexpected text; expected elements only");
      continue;
    }
    if (c.type() != pugi::node_element) continue;
    bool ok = false;
    for (auto x : children) ok = ok || x == c.name();
    if (!ok) {
      std::string list;
      for (auto x : children) list += (list.empty() ? "" : ", ") + std::string(x);
      return err(Errc::parse_error, c,
                 "unexpected element; expected " + (list.empty() ? "none" : "one of: " + list));
    }
  }
  return {};
}

Result<xml_node> XmlReader::single(xml_node n, const char* name, bool required) const {
  xml_node c = n.child(name);
  if (!c) {
    if (required) return err(Errc::parse_error, n, "missing element <" + std::string(name) + ">");
    return c;
  }
  if (xml_node d = c.next_sibling(name))
    return err(Errc::parse_error, d, "element <" + std::string(name) + "> appears twice");
  return c;
}

Result<std::string> XmlReader::attr(xml_node n, const char* name, bool required) const {
  auto a = n.attribute(name);
  if (!a) {
    if (required)
      return err(Errc::parse_error, n, "missing attribute \"" + std::string(name) + "\"");
    return std::string();
  }
  return std::string(a.value());
}

Result<std::uint64_t> XmlReader::uint_attr(xml_node n, const char* name, std::uint64_t max,
                                           std::string_view what) const {
  LMCFG_ASSIGN_OR_RETURN(auto s, attr(n, name, true));
  auto v = parse_decimal(s);
  if (!v || *v > max)
    return err_attr(Errc::parse_error, n, name,
                    "expected " + std::string(what) + " (0.." + std::to_string(max) +
                        " in decimal), found \"" + s + "\"");
  return *v;
}

Result<std::int64_t> XmlReader::int_attr(xml_node n, const char* name,
                                         std::string_view what) const {
  LMCFG_ASSIGN_OR_RETURN(auto s, attr(n, name, true));
  auto v = parse_signed_decimal(s);
  if (!v)
    return err_attr(Errc::parse_error, n, name,
                    "expected " + std::string(what) + ", found \"" + s + "\"");
  return *v;
}

Result<bool> XmlReader::bool_attr(xml_node n, const char* name) const {
  LMCFG_ASSIGN_OR_RETURN(auto s, attr(n, name, true));
  if (s == "true") return true;
  if (s == "false") return false;
  return err_attr(Errc::parse_error, n, name, "expected true or false, found \"" + s + "\"");
}

Result<std::string> XmlReader::text(xml_node n,
                                    std::initializer_list<std::string_view> attrs) const {
  for (auto a : n.attributes()) {
    bool ok = false;
    for (auto x : attrs) ok = ok || x == a.name();
    if (!ok) return err_attr(Errc::parse_error, n, a.name(), "unexpected attribute");
  }
  std::string s;
  for (auto c : n.children()) {
    if (c.type() == pugi::node_pcdata || c.type() == pugi::node_cdata) {
      s += c.value();
    } else if (c.type() == pugi::node_element) {
      return err(Errc::parse_error, c, "unexpected element; expected text only");
    }
  }
  return s;
}

Result<void> XmlReader::opt_text(xml_node parent, const char* name, std::string& out) const {
  LMCFG_ASSIGN_OR_RETURN(xml_node c, single(parent, name, false));
  if (c) {
    LMCFG_ASSIGN_OR_RETURN(out, text(c));
  }
  return {};
}

Result<Bytes> XmlReader::rows(xml_node n) const {
  LMCFG_TRY(shape(n, {}, {"row"}));
  Bytes out;
  for (xml_node r : n.children("row")) {
    LMCFG_ASSIGN_OR_RETURN(auto s, text(r));
    auto b = parse_row(s);
    if (!b)
      return err(Errc::parse_error, r,
                 "expected 1..16 hex bytes separated by single spaces (\"46 00 03 00\"), found \"" +
                     s.substr(0, 60) + "\"");
    out.insert(out.end(), b->begin(), b->end());
  }
  return out;
}

Result<void> XmlReader::since(xml_node n, const fields::Spec& s) const {
  if (version_ >= s.since) return {};
  const std::string key(s.key);
  const std::string msg = "the " + key + " field is new in format_version " +
                          std::to_string(s.since) + ", this file says " + std::to_string(version_);
  if (n.attribute(key.c_str()))
    return err_attr(Errc::parse_error, n, key, "unexpected attribute; " + msg);
  if (xml_node c = n.child(key.c_str()))
    return err(Errc::parse_error, c, "unexpected element; " + msg);
  return {};
}

Result<void> XmlReader::read_value(xml_node n, const fields::Spec& s,
                                   const fields::Ref& ref) const {
  if (fields::xml_element(s)) return read_element(n, s, ref);
  const std::string key(s.key);
  const char* k = key.c_str();
  if (s.use != Use::required && !n.attribute(k)) return {};
  if (s.kind == Kind::number) {
    LMCFG_ASSIGN_OR_RETURN(auto v, uint_attr(n, k, s.max, s.what));
    fields::set_number(ref, v);
    return {};
  }
  if (s.kind == Kind::flag) {
    LMCFG_ASSIGN_OR_RETURN(*std::get<bool*>(ref), bool_attr(n, k));
    return {};
  }
  LMCFG_ASSIGN_OR_RETURN(auto value, attr(n, k, true));
  const auto bad = [&](const std::string& expected) {
    return err_attr(Errc::parse_error, n, k, "expected " + expected + ", found \"" + value + "\"");
  };
  switch (s.kind) {
    case Kind::text:
      *std::get<std::string*>(ref) = std::move(value);
      return {};
    case Kind::upid: {
      const auto upid = parse_upid_hex(value);
      if (!upid) return bad("a UPID as 4 hex digits (\"13A2\")");
      *std::get<std::uint16_t*>(ref) = *upid;
      return {};
    }
    case Kind::motor: {
      const auto motor = parse_devicenet_motor(value);
      if (!motor) return bad("\"controller\" or a motor \"A\"..\"D\"");
      *std::get<int*>(ref) = *motor;
      return {};
    }
    case Kind::command: {
      const auto command = parse_command_hex(value);
      if (!command) return bad("a command ID as 2 hex digits (\"34\")");
      *std::get<std::uint8_t*>(ref) = *command;
      return {};
    }
    case Kind::param_set: {
      const auto set = param_set_from_string(value);
      if (!set) return bad("\"modified\" or \"full\"");
      *std::get<ParamSet*>(ref) = *set;
      return {};
    }
    case Kind::layer_set: {
      auto& layers = *std::get<std::array<bool, lmcfg::layers::kCount>*>(ref);
      layers = {};
      std::istringstream words(value);
      std::string tok;
      while (words >> tok) {
        if (tok.size() != 1 || tok[0] < '1' || tok[0] > '4')
          return bad("layer numbers 1..4 separated by spaces");
        auto& flag = layers[static_cast<std::size_t>(tok[0] - '1')];
        if (flag) return err_attr(Errc::validation_failed, n, k, "layer " + tok + " listed twice");
        flag = true;
      }
      return {};
    }
    case Kind::motor_list: {
      std::istringstream words(value);
      std::string tok;
      while (words >> tok) {
        const auto m = parse_motor_letter(tok);
        if (!m) return bad("motors A..D separated by spaces");
        std::get<std::vector<int>*>(ref)->push_back(*m);
      }
      return {};
    }
    default:
      return {};
  }
}

// A field in an element of its own.
Result<void> XmlReader::read_element(xml_node n, const fields::Spec& s,
                                     const fields::Ref& ref) const {
  const std::string key(s.key), item(s.item);
  LMCFG_ASSIGN_OR_RETURN(xml_node e, single(n, key.c_str(), s.use == Use::required));
  if (!e) return {};
  const std::string_view items[] = {s.item};
  switch (s.kind) {
    case Kind::text: {
      LMCFG_ASSIGN_OR_RETURN(*std::get<std::string*>(ref), text(e));
      return {};
    }
    case Kind::rows: {
      LMCFG_ASSIGN_OR_RETURN(*std::get<Bytes*>(ref), rows(e));
      return {};
    }
    case Kind::text_list:
      LMCFG_TRY(shape(e, std::span<const std::string_view>(), items));
      for (xml_node c : e.children(item.c_str())) {
        LMCFG_ASSIGN_OR_RETURN(auto t, text(c));
        std::get<std::vector<std::string>*>(ref)->push_back(std::move(t));
      }
      return {};
    case Kind::label_map:
      LMCFG_TRY(shape(e, std::span<const std::string_view>(), items));
      for (xml_node c : e.children(item.c_str())) {
        LMCFG_ASSIGN_OR_RETURN(auto label, attr(c, "key", true));
        LMCFG_ASSIGN_OR_RETURN(auto value, text(c, {"key"}));
        if (!std::get<std::map<std::string, std::string>*>(ref)->emplace(label, value).second)
          return err_attr(Errc::validation_failed, c, "key", "duplicate label \"" + label + "\"");
      }
      return {};
    case Kind::value_list:
      LMCFG_TRY(shape(e, std::span<const std::string_view>(), items));
      for (xml_node c : e.children(item.c_str())) {
        DevicenetValue v;
        LMCFG_TRY(read_record(c, fields::devicenet_value_fields(), v));
        std::get<std::vector<DevicenetValue>*>(ref)->push_back(std::move(v));
      }
      return {};
    default:
      return {};
  }
}

void write_value(xml_node n, const fields::Spec& s, const fields::Ref& ref) {
  const std::string key(s.key), item(s.item);
  const char* k = key.c_str();
  const auto words = [](const auto& list, auto&& word) {
    std::string out;
    for (const auto& x : list) out += (out.empty() ? "" : " ") + word(x);
    return out;
  };
  switch (s.kind) {
    case Kind::text: {
      const auto& v = *std::get<std::string*>(ref);
      if (s.use == Use::nonempty && v.empty()) return;
      if (s.xml == fields::Xml::attribute) {
        n.append_attribute(k) = v.c_str();
      } else if (xml_node e = n.append_child(k); !v.empty()) {
        e.text().set(v.c_str());
      }
      return;
    }
    case Kind::upid:
      n.append_attribute(k) = upid_hex(*std::get<std::uint16_t*>(ref)).c_str();
      return;
    case Kind::number:
      if (auto v = fields::number_of(ref))
        n.append_attribute(k) = static_cast<unsigned long long>(*v);
      return;
    case Kind::flag:
      n.append_attribute(k) = *std::get<bool*>(ref) ? "true" : "false";
      return;
    case Kind::rows: {
      xml_node e = n.append_child(k);
      for (const auto& r : block_rows(*std::get<Bytes*>(ref)))
        e.append_child("row").text().set(r.c_str());
      return;
    }
    case Kind::motor:
      n.append_attribute(k) = devicenet_motor_text(*std::get<int*>(ref)).c_str();
      return;
    case Kind::command:
      n.append_attribute(k) = command_hex(*std::get<std::uint8_t*>(ref)).c_str();
      return;
    case Kind::param_set:
      n.append_attribute(k) = std::string(to_string(*std::get<ParamSet*>(ref))).c_str();
      return;
    case Kind::layer_set: {
      const auto& layers = *std::get<std::array<bool, lmcfg::layers::kCount>*>(ref);
      std::vector<int> numbers;
      for (int l = 1; l <= lmcfg::layers::kCount; ++l)
        if (layers[static_cast<std::size_t>(l - 1)]) numbers.push_back(l);
      n.append_attribute(k) = words(numbers, [](int l) { return std::to_string(l); }).c_str();
      return;
    }
    case Kind::motor_list:
      n.append_attribute(k) =
          words(*std::get<std::vector<int>*>(ref), devicenet_motor_text).c_str();
      return;
    case Kind::text_list: {
      const auto& list = *std::get<std::vector<std::string>*>(ref);
      if (s.use == Use::nonempty && list.empty()) return;
      xml_node e = n.append_child(k);
      for (const auto& t : list) e.append_child(item.c_str()).text().set(t.c_str());
      return;
    }
    case Kind::label_map: {
      xml_node e = n.append_child(k);
      for (const auto& [label, v] : *std::get<std::map<std::string, std::string>*>(ref)) {
        xml_node l = e.append_child(item.c_str());
        l.append_attribute("key") = label.c_str();
        if (!v.empty()) l.text().set(v.c_str());
      }
      return;
    }
    case Kind::value_list: {
      xml_node e = n.append_child(k);
      for (const auto& v : *std::get<std::vector<DevicenetValue>*>(ref))
        write_record(e.append_child(item.c_str()), fields::devicenet_value_fields(), v);
      return;
    }
    case Kind::group:  // write_record writes groups
      return;
  }
}

}  // namespace lmcfg::config::detail
