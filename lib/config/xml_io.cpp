#include "config/xml_io.hpp"

#include <pugixml.hpp>
#include <set>
#include <sstream>
#include <utility>

#include "common/layers.hpp"
#include "config/atomic_file.hpp"
#include "config/io_common.hpp"
#include "config/json_io.hpp"  // text_position
#include "config/migrate.hpp"

namespace lmcfg::config {
namespace {

using pugi::xml_node;

constexpr unsigned kParseFlags =
    pugi::parse_cdata | pugi::parse_escapes | pugi::parse_eol | pugi::parse_ws_pcdata_single;

bool is_repeated(std::string_view name) {
  return name == "layer" || name == "param" || name == "curve" || name == "entry" ||
         name == "row" || name == "label" || name == "setpoint" || name == "module" ||
         name == "value";
}

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

bool blank(const char* s) {
  for (; *s; ++s)
    if (*s != ' ' && *s != '\t' && *s != '\n' && *s != '\r') return false;
  return true;
}

// The elements read_v2 read, to locate a validation issue of the model.
struct Nodes {
  xml_node identity, labels, scope, parameters;
  std::array<xml_node, lmcfg::layers::kCount> layers{};
  std::array<std::vector<xml_node>, lmcfg::layers::kCount> params;  // <param> per layer
  std::vector<xml_node> curves, entries;
  xml_node devicenet;
  std::vector<xml_node> dn_values, dn_live;  // <value> of <values> / <live>
};

// The XPath-like location of a validation issue of the model.
std::string issue_path(const Issue& is, const Nodes& nodes) {
  std::string path;
  switch (is.where) {
    case Issue::Where::identity: {
      const std::string base = nodes.identity ? node_path(nodes.identity) : "/lmcfg/identity";
      const std::string& f = is.field;
      if (f.rfind("labels.", 0) == 0) {
        path = nodes.labels ? node_path(nodes.labels) : base + "/labels";
        for (xml_node l : nodes.labels.children("label"))
          if (f.substr(7) == l.attribute("key").value()) path = node_path(l);
      } else if (auto dot = f.find('.'); dot != std::string::npos) {
        path = base + "/" + f.substr(0, dot) + "/@" + f.substr(dot + 1);
      } else {
        path = base + "/" + f;
      }
      break;
    }
    case Issue::Where::scope:
      path = node_path(nodes.scope) + "/@" + is.field;
      break;
    case Issue::Where::layer: {
      xml_node ln = nodes.layers[static_cast<std::size_t>(is.layer - 1)];
      path = ln ? node_path(ln) : node_path(nodes.parameters);
      break;
    }
    case Issue::Where::param:
      path = node_path(nodes.params[static_cast<std::size_t>(is.layer - 1)].at(is.index)) + "/@" +
             is.field;
      break;
    case Issue::Where::curve: {
      xml_node cn = nodes.curves.at(is.index);
      path = is.field == "id" ? node_path(cn) + "/@id" : node_path(cn.child(is.field.c_str()));
      break;
    }
    case Issue::Where::ct_entry: {
      xml_node en = nodes.entries.at(is.index);
      path = is.field == "id" ? node_path(en) + "/@id" : node_path(en.child(is.field.c_str()));
      break;
    }
    case Issue::Where::devicenet: {
      xml_node modules = nodes.devicenet.child("io_modules");
      path = is.field == "io_modules" ? node_path(modules ? modules : nodes.devicenet)
                                      : node_path(nodes.devicenet) + "/@" + is.field;
      break;
    }
    case Issue::Where::devicenet_value:
      path = node_path((is.live ? nodes.dn_live : nodes.dn_values).at(is.index)) + "/@" + is.field;
      break;
  }
  return path;
}

class Reader {
 public:
  explicit Reader(std::string_view name) : name_(name) {}

  Error err(Errc e, xml_node n, const std::string& msg) const {
    return Error(e, name_ + ": " + node_path(n) + ": " + msg);
  }
  Error err_attr(Errc e, xml_node n, std::string_view attr, const std::string& msg) const {
    return Error(e, name_ + ": " + node_path(n) + "/@" + std::string(attr) + ": " + msg);
  }
  std::string where(xml_node n) const { return name_ + ": " + node_path(n); }

  // Only the listed attributes and child elements; no text besides blanks.
  Result<void> shape(xml_node n, std::initializer_list<std::string_view> attrs,
                     std::initializer_list<std::string_view> children) const {
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
  // The single child element `name` (null when absent and optional).
  Result<xml_node> single(xml_node n, const char* name, bool required) const {
    xml_node c = n.child(name);
    if (!c) {
      if (required) return err(Errc::parse_error, n, "missing element <" + std::string(name) + ">");
      return c;
    }
    if (xml_node d = c.next_sibling(name))
      return err(Errc::parse_error, d, "element <" + std::string(name) + "> appears twice");
    return c;
  }
  Result<std::string> attr(xml_node n, const char* name, bool required) const {
    auto a = n.attribute(name);
    if (!a) {
      if (required)
        return err(Errc::parse_error, n, "missing attribute \"" + std::string(name) + "\"");
      return std::string();
    }
    return std::string(a.value());
  }
  Result<std::uint64_t> uint_attr(xml_node n, const char* name, std::uint64_t max,
                                  std::string_view what) const {
    LMCFG_ASSIGN_OR_RETURN(auto s, attr(n, name, true));
    auto v = detail::parse_decimal(s);
    if (!v || *v > max)
      return err_attr(Errc::parse_error, n, name,
                      "expected " + std::string(what) + " (0.." + std::to_string(max) +
                          " in decimal), found \"" + s + "\"");
    return *v;
  }
  Result<std::int64_t> int_attr(xml_node n, const char* name, std::string_view what) const {
    LMCFG_ASSIGN_OR_RETURN(auto s, attr(n, name, true));
    auto v = detail::parse_signed_decimal(s);
    if (!v)
      return err_attr(Errc::parse_error, n, name,
                      "expected " + std::string(what) + ", found \"" + s + "\"");
    return *v;
  }
  Result<bool> bool_attr(xml_node n, const char* name) const {
    LMCFG_ASSIGN_OR_RETURN(auto s, attr(n, name, true));
    if (s == "true") return true;
    if (s == "false") return false;
    return err_attr(Errc::parse_error, n, name, "expected true or false, found \"" + s + "\"");
  }
  // Text of an element holding only text.
  Result<std::string> text(xml_node n, std::initializer_list<std::string_view> attrs = {}) const {
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
  Result<void> opt_text(xml_node parent, const char* name, std::string& out) const {
    LMCFG_ASSIGN_OR_RETURN(xml_node c, single(parent, name, false));
    if (c) {
      LMCFG_ASSIGN_OR_RETURN(out, text(c));
    }
    return {};
  }
  Result<Bytes> rows(xml_node n) const {
    LMCFG_TRY(shape(n, {}, {"row"}));
    Bytes out;
    for (xml_node r : n.children("row")) {
      LMCFG_ASSIGN_OR_RETURN(auto s, text(r));
      auto b = detail::parse_row(s);
      if (!b)
        return err(
            Errc::parse_error, r,
            "expected 1..16 hex bytes separated by single spaces (\"46 00 03 00\"), found \"" +
                s.substr(0, 60) + "\"");
      out.insert(out.end(), b->begin(), b->end());
    }
    return out;
  }

  Result<DriveConfig> read_document(const pugi::xml_document& doc);

 private:
  // The phases of read_v2: one element of the document each.
  Result<DriveConfig> read_v2(xml_node root, std::int64_t version);
  Result<void> read_identity(xml_node root, Identity& id, Nodes& nodes) const;
  Result<void> read_scope(xml_node root, Scope& scope_out, Nodes& nodes) const;
  Result<void> read_parameters(xml_node root, DriveConfig& cfg, Nodes& nodes) const;
  Result<Parameter> read_parameter(xml_node pn) const;
  Result<void> read_curves(xml_node root, std::vector<Curve>& out, Nodes& nodes) const;
  Result<void> read_command_table(xml_node root, std::vector<CtEntry>& out, Nodes& nodes) const;
  Result<void> read_devicenet(xml_node root, std::optional<DevicenetSection>& out,
                              Nodes& nodes) const;
  Result<void> read_devicenet_values(xml_node list, std::vector<DevicenetValue>& out,
                                     std::vector<xml_node>& nodes) const;
  Result<ConfigV1> read_v1(xml_node root);
  std::string name_;
};

Result<DriveConfig> Reader::read_document(const pugi::xml_document& doc) {
  xml_node root = doc.document_element();
  if (!root || std::string_view(root.name()) != "lmcfg")
    return Error(Errc::parse_error, name_ + ": " + (root ? node_path(root) : std::string("/")) +
                                        ": expected the root element <lmcfg>");
  LMCFG_ASSIGN_OR_RETURN(auto fmt, attr(root, "format", true));
  LMCFG_TRY(detail::check_format_id(fmt, where(root) + "/@format"));
  LMCFG_ASSIGN_OR_RETURN(auto version,
                         int_attr(root, "format_version", "an integer format version"));
  LMCFG_TRY(detail::check_format_version(version, name_, where(root) + "/@format_version"));
  if (version == 1) {
    LMCFG_ASSIGN_OR_RETURN(auto v1, read_v1(root));
    return migrate_v1_to_v2(v1);
  }
  return read_v2(root, version);
}

// Versions 2 and 3: a version 2 file is a version 3 file without <devicenet>.
Result<DriveConfig> Reader::read_v2(xml_node root, std::int64_t version) {
  if (xml_node dn = root.child("devicenet"); dn && version < 3)
    return err(Errc::parse_error, dn,
               "unexpected element; the devicenet section is new in format_version 3, this file "
               "says " +
                   std::to_string(version));
  LMCFG_TRY(shape(root, {"format", "format_version"},
                  {"identity", "scope", "parameters", "curves", "command_table", "devicenet"}));
  DriveConfig cfg;
  Nodes nodes;
  LMCFG_TRY(read_identity(root, cfg.identity, nodes));
  LMCFG_TRY(read_scope(root, cfg.scope, nodes));
  LMCFG_TRY(read_parameters(root, cfg, nodes));
  LMCFG_TRY(read_curves(root, cfg.curves, nodes));
  LMCFG_TRY(read_command_table(root, cfg.ct_entries, nodes));
  LMCFG_TRY(read_devicenet(root, cfg.devicenet, nodes));
  if (auto is = find_issue(cfg))
    return Error(Errc::validation_failed,
                 name_ + ": " + issue_path(*is, nodes) + ": " + is->message);
  canonicalize(cfg);
  return cfg;
}

// identity (optional; every element optional)
Result<void> Reader::read_identity(xml_node root, Identity& id, Nodes& nodes) const {
  LMCFG_ASSIGN_OR_RETURN(nodes.identity, single(root, "identity", false));
  const xml_node idn = nodes.identity;
  if (!idn) return {};
  LMCFG_TRY(shape(idn, {},
                  {"macid", "link", "product", "firmware", "upid_fingerprint", "tool_version",
                   "upid_db", "captured_at", "labels"}));
  LMCFG_TRY(opt_text(idn, "macid", id.macid));
  LMCFG_TRY(opt_text(idn, "product", id.product));
  LMCFG_TRY(opt_text(idn, "firmware", id.firmware));
  LMCFG_TRY(opt_text(idn, "upid_fingerprint", id.upid_fingerprint));
  LMCFG_TRY(opt_text(idn, "tool_version", id.tool_version));
  LMCFG_TRY(opt_text(idn, "captured_at", id.captured_at));
  LMCFG_ASSIGN_OR_RETURN(xml_node link, single(idn, "link", false));
  if (link) {
    LMCFG_TRY(shape(link, {"port", "baud", "parity", "stop_bits", "checksum"}, {}));
    LMCFG_ASSIGN_OR_RETURN(id.link.port, attr(link, "port", false));
    LMCFG_ASSIGN_OR_RETURN(id.link.baud, attr(link, "baud", false));
    LMCFG_ASSIGN_OR_RETURN(id.link.parity, attr(link, "parity", false));
    LMCFG_ASSIGN_OR_RETURN(id.link.stop_bits, attr(link, "stop_bits", false));
    LMCFG_ASSIGN_OR_RETURN(id.link.checksum, attr(link, "checksum", false));
  }
  LMCFG_ASSIGN_OR_RETURN(xml_node db, single(idn, "upid_db", false));
  if (db) {
    LMCFG_TRY(shape(db, {"version", "hash"}, {}));
    LMCFG_ASSIGN_OR_RETURN(id.upid_db_version, attr(db, "version", false));
    LMCFG_ASSIGN_OR_RETURN(id.upid_db_hash, attr(db, "hash", false));
  }
  LMCFG_ASSIGN_OR_RETURN(nodes.labels, single(idn, "labels", false));
  if (nodes.labels) {
    LMCFG_TRY(shape(nodes.labels, {}, {"label"}));
    for (xml_node l : nodes.labels.children("label")) {
      LMCFG_ASSIGN_OR_RETURN(auto key, attr(l, "key", true));
      LMCFG_ASSIGN_OR_RETURN(auto value, text(l, {"key"}));
      if (!id.labels.emplace(key, value).second)
        return err_attr(Errc::validation_failed, l, "key", "duplicate label \"" + key + "\"");
    }
  }
  return {};
}

// scope (required)
Result<void> Reader::read_scope(xml_node root, Scope& scope_out, Nodes& nodes) const {
  LMCFG_ASSIGN_OR_RETURN(nodes.scope, single(root, "scope", true));
  const xml_node scope = nodes.scope;
  LMCFG_TRY(shape(scope, {"layers", "parameters", "curves", "command_table"}, {}));
  LMCFG_ASSIGN_OR_RETURN(auto layers, attr(scope, "layers", true));
  scope_out.layers = {false, false, false, false};
  std::istringstream ls(layers);
  std::string tok;
  while (ls >> tok) {
    if (tok.size() != 1 || tok[0] < '1' || tok[0] > '4')
      return err_attr(Errc::parse_error, scope, "layers",
                      "expected layer numbers 1..4 separated by spaces, found \"" + layers + "\"");
    auto& flag = scope_out.layers[static_cast<std::size_t>(tok[0] - '1')];
    if (flag)
      return err_attr(Errc::validation_failed, scope, "layers", "layer " + tok + " listed twice");
    flag = true;
  }
  LMCFG_ASSIGN_OR_RETURN(auto ps, attr(scope, "parameters", true));
  auto set = param_set_from_string(ps);
  if (!set)
    return err_attr(Errc::parse_error, scope, "parameters",
                    "expected \"modified\" or \"full\", found \"" + ps + "\"");
  scope_out.parameters = *set;
  LMCFG_ASSIGN_OR_RETURN(scope_out.curves, bool_attr(scope, "curves"));
  LMCFG_ASSIGN_OR_RETURN(scope_out.command_table, bool_attr(scope, "command_table"));
  return {};
}

// parameters (required)
Result<void> Reader::read_parameters(xml_node root, DriveConfig& cfg, Nodes& nodes) const {
  LMCFG_ASSIGN_OR_RETURN(nodes.parameters, single(root, "parameters", true));
  const xml_node params = nodes.parameters;
  LMCFG_TRY(shape(params, {}, {"layer"}));
  for (xml_node ln : params.children("layer")) {
    LMCFG_TRY(shape(ln, {"number", "name"}, {"param"}));
    LMCFG_ASSIGN_OR_RETURN(auto l, uint_attr(ln, "number", 4, "a layer number"));
    if (l < 1)
      return err_attr(Errc::parse_error, ln, "number",
                      "expected a layer number (1..4), found \"0\"");
    const auto li = static_cast<std::size_t>(l - 1);
    if (nodes.layers[li])
      return err_attr(Errc::validation_failed, ln, "number",
                      "layer " + std::to_string(l) + " appears twice");
    nodes.layers[li] = ln;
    auto& out = cfg.layer(static_cast<int>(l));
    for (xml_node pn : ln.children("param")) {
      LMCFG_ASSIGN_OR_RETURN(Parameter prm, read_parameter(pn));
      out.push_back(std::move(prm));
      nodes.params[li].push_back(pn);
    }
  }
  return {};
}

// One <param> of a layer.
Result<Parameter> Reader::read_parameter(xml_node pn) const {
  LMCFG_TRY(shape(pn, {"upid", "value", "type", "default", "name", "unit", "scaled"}, {}));
  Parameter prm;
  LMCFG_ASSIGN_OR_RETURN(auto us, attr(pn, "upid", true));
  auto upid = detail::parse_upid_hex(us);
  if (!upid)
    return err_attr(Errc::parse_error, pn, "upid",
                    "expected a UPID as 4 hex digits (\"13A2\"), found \"" + us + "\"");
  prm.upid = *upid;
  LMCFG_ASSIGN_OR_RETURN(auto v, uint_attr(pn, "value", 0xFFFFFFFFu, "an unsigned 32-bit value"));
  prm.value = static_cast<std::uint32_t>(v);
  if (pn.attribute("type")) {
    LMCFG_ASSIGN_OR_RETURN(auto t, uint_attr(pn, "type", 15, "a type code"));
    prm.type = static_cast<std::uint8_t>(t);
  }
  if (pn.attribute("default")) {
    LMCFG_ASSIGN_OR_RETURN(auto d,
                           uint_attr(pn, "default", 0xFFFFFFFFu, "an unsigned 32-bit value"));
    prm.default_value = static_cast<std::uint32_t>(d);
  }
  LMCFG_ASSIGN_OR_RETURN(prm.name, attr(pn, "name", false));
  LMCFG_ASSIGN_OR_RETURN(prm.unit, attr(pn, "unit", false));
  LMCFG_ASSIGN_OR_RETURN(prm.scaled, attr(pn, "scaled", false));
  return prm;
}

// curves (optional)
Result<void> Reader::read_curves(xml_node root, std::vector<Curve>& out, Nodes& nodes) const {
  LMCFG_ASSIGN_OR_RETURN(xml_node curves, single(root, "curves", false));
  if (curves) {
    LMCFG_TRY(shape(curves, {}, {"curve"}));
    for (xml_node cn : curves.children("curve")) {
      LMCFG_TRY(shape(cn, {"id"}, {"info", "data", "decoded"}));
      Curve c;
      LMCFG_ASSIGN_OR_RETURN(auto cid, uint_attr(cn, "id", 0xFFFF, "a curve ID"));
      c.id = static_cast<std::uint32_t>(cid);
      LMCFG_ASSIGN_OR_RETURN(xml_node info, single(cn, "info", true));
      LMCFG_ASSIGN_OR_RETURN(c.info, rows(info));
      LMCFG_ASSIGN_OR_RETURN(xml_node data, single(cn, "data", true));
      LMCFG_ASSIGN_OR_RETURN(c.data, rows(data));
      LMCFG_TRY(single(cn, "decoded", false));  // derived: not read
      out.push_back(std::move(c));
      nodes.curves.push_back(cn);
    }
  }
  return {};
}

// command table (optional)
Result<void> Reader::read_command_table(xml_node root, std::vector<CtEntry>& out,
                                        Nodes& nodes) const {
  LMCFG_ASSIGN_OR_RETURN(xml_node table, single(root, "command_table", false));
  if (table) {
    LMCFG_TRY(shape(table, {}, {"entry"}));
    for (xml_node en : table.children("entry")) {
      LMCFG_TRY(shape(en, {"id"}, {"raw", "decoded"}));
      CtEntry e;
      LMCFG_ASSIGN_OR_RETURN(auto eid, uint_attr(en, "id", 0xFFFFFFFFu, "an entry ID"));
      e.id = static_cast<std::uint32_t>(eid);
      LMCFG_ASSIGN_OR_RETURN(xml_node raw, single(en, "raw", true));
      LMCFG_ASSIGN_OR_RETURN(e.raw, rows(raw));
      LMCFG_TRY(single(en, "decoded", false));
      out.push_back(std::move(e));
      nodes.entries.push_back(en);
    }
  }
  return {};
}

// devicenet (optional, format_version 3)
Result<void> Reader::read_devicenet(xml_node root, std::optional<DevicenetSection>& out,
                                    Nodes& nodes) const {
  LMCFG_ASSIGN_OR_RETURN(nodes.devicenet, single(root, "devicenet", false));
  const xml_node dnn = nodes.devicenet;
  if (!dnn) return {};
  LMCFG_TRY(shape(dnn, {"can_bitrate", "motors"}, {"io_modules", "values", "live"}));
  DevicenetSection dn;
  LMCFG_ASSIGN_OR_RETURN(auto rate, uint_attr(dnn, "can_bitrate", 0xFFFFFFFFu, "a CAN bit rate"));
  dn.can_bitrate = static_cast<std::uint32_t>(rate);
  LMCFG_ASSIGN_OR_RETURN(auto motors, attr(dnn, "motors", true));
  std::istringstream ms(motors);
  std::string tok;
  while (ms >> tok) {
    const auto m = detail::parse_motor_letter(tok);
    if (!m)
      return err_attr(Errc::parse_error, dnn, "motors",
                      "expected motors A..D separated by spaces, found \"" + motors + "\"");
    dn.motors.push_back(*m);
  }
  LMCFG_ASSIGN_OR_RETURN(xml_node modules, single(dnn, "io_modules", false));
  if (modules) {
    LMCFG_TRY(shape(modules, {}, {"module"}));
    for (xml_node mn : modules.children("module")) {
      LMCFG_ASSIGN_OR_RETURN(auto m, text(mn));
      dn.io_modules.push_back(std::move(m));
    }
  }
  LMCFG_ASSIGN_OR_RETURN(xml_node values, single(dnn, "values", false));
  if (values) LMCFG_TRY(read_devicenet_values(values, dn.values, nodes.dn_values));
  LMCFG_ASSIGN_OR_RETURN(xml_node live, single(dnn, "live", false));
  if (live) LMCFG_TRY(read_devicenet_values(live, dn.live, nodes.dn_live));
  out = std::move(dn);
  return {};
}

// The <value> elements of <values> or <live>.
Result<void> Reader::read_devicenet_values(xml_node list, std::vector<DevicenetValue>& out,
                                           std::vector<xml_node>& nodes) const {
  LMCFG_TRY(shape(list, {}, {"value"}));
  for (xml_node vn : list.children("value")) {
    LMCFG_TRY(shape(vn, {"motor", "command", "raw", "name", "scaled", "unit"}, {}));
    DevicenetValue v;
    LMCFG_ASSIGN_OR_RETURN(auto ms, attr(vn, "motor", true));
    const auto motor = detail::parse_devicenet_motor(ms);
    if (!motor)
      return err_attr(Errc::parse_error, vn, "motor",
                      "expected \"controller\" or a motor \"A\"..\"D\", found \"" + ms + "\"");
    v.motor = *motor;
    LMCFG_ASSIGN_OR_RETURN(auto cs, attr(vn, "command", true));
    const auto command = detail::parse_command_hex(cs);
    if (!command)
      return err_attr(Errc::parse_error, vn, "command",
                      "expected a command ID as 2 hex digits (\"34\"), found \"" + cs + "\"");
    v.command = *command;
    LMCFG_ASSIGN_OR_RETURN(auto raw, uint_attr(vn, "raw", 0xFFFF, "a 16-bit word"));
    v.raw = static_cast<std::uint16_t>(raw);
    LMCFG_ASSIGN_OR_RETURN(v.name, attr(vn, "name", false));
    LMCFG_ASSIGN_OR_RETURN(v.scaled, attr(vn, "scaled", false));
    LMCFG_ASSIGN_OR_RETURN(v.unit, attr(vn, "unit", false));
    out.push_back(std::move(v));
    nodes.push_back(vn);
  }
  return {};
}

Result<ConfigV1> Reader::read_v1(xml_node root) {
  LMCFG_TRY(shape(root, {"format", "format_version"},
                  {"drive", "parameters", "curves", "command_table"}));
  ConfigV1 v1;
  v1.field_sep = "/@";
  LMCFG_ASSIGN_OR_RETURN(xml_node drive, single(root, "drive", false));
  if (drive) {
    LMCFG_TRY(shape(
        drive,
        {"macid", "port", "baud", "parity", "stop_bits", "checksum", "tool_version", "captured_at"},
        {}));
    LMCFG_ASSIGN_OR_RETURN(v1.macid, attr(drive, "macid", false));
    LMCFG_ASSIGN_OR_RETURN(v1.port, attr(drive, "port", false));
    LMCFG_ASSIGN_OR_RETURN(v1.parity, attr(drive, "parity", false));
    LMCFG_ASSIGN_OR_RETURN(v1.stop_bits, attr(drive, "stop_bits", false));
    LMCFG_ASSIGN_OR_RETURN(v1.checksum, attr(drive, "checksum", false));
    LMCFG_ASSIGN_OR_RETURN(v1.tool_version, attr(drive, "tool_version", false));
    LMCFG_ASSIGN_OR_RETURN(v1.captured_at, attr(drive, "captured_at", false));
    if (drive.attribute("baud")) {
      LMCFG_ASSIGN_OR_RETURN(auto baud, uint_attr(drive, "baud", 0xFFFFFFFFu, "a baud rate"));
      v1.baud = std::to_string(baud);
    }
  }
  LMCFG_ASSIGN_OR_RETURN(xml_node params, single(root, "parameters", true));
  LMCFG_TRY(shape(params, {}, {"param"}));
  for (xml_node pn : params.children("param")) {
    LMCFG_TRY(shape(pn, {"upid", "value"}, {}));
    ConfigV1::Param p;
    LMCFG_ASSIGN_OR_RETURN(p.upid, int_attr(pn, "upid", "a decimal UPID"));
    LMCFG_ASSIGN_OR_RETURN(p.value, int_attr(pn, "value", "a decimal value"));
    p.where = where(pn);
    v1.params.push_back(std::move(p));
  }
  auto blocks = [&](const char* list, const char* item, bool curve,
                    std::vector<ConfigV1::Block>& out) -> Result<void> {
    LMCFG_ASSIGN_OR_RETURN(xml_node ln, single(root, list, false));
    if (!ln) return {};
    LMCFG_TRY(shape(ln, {}, {item}));
    for (xml_node n : ln.children(item)) {
      if (curve) {
        LMCFG_TRY(shape(n, {"id", "info", "data"}, {}));
      } else {
        LMCFG_TRY(shape(n, {"id", "data"}, {}));
      }
      ConfigV1::Block b;
      LMCFG_ASSIGN_OR_RETURN(b.id, int_attr(n, "id", "a decimal ID"));
      for (const char* field : {"info", "data"}) {
        if (!curve && std::string_view(field) == "info") continue;
        LMCFG_ASSIGN_OR_RETURN(auto hs, attr(n, field, true));
        auto bytes = from_hex(hs);
        if (!bytes)
          return err_attr(Errc::parse_error, n, field, "expected hex bytes (\"46 00 03 00\")");
        (std::string_view(field) == "info" ? b.info : b.data) = std::move(*bytes);
      }
      b.where = where(n);
      out.push_back(std::move(b));
    }
    return {};
  };
  LMCFG_TRY(blocks("curves", "curve", true, v1.curves));
  LMCFG_TRY(blocks("command_table", "entry", false, v1.ct_entries));
  return v1;
}

void add_rows(xml_node parent, const char* name, ByteView b) {
  xml_node n = parent.append_child(name);
  for (const auto& r : detail::block_rows(b)) n.append_child("row").text().set(r.c_str());
}

void text_child(xml_node parent, const char* name, const std::string& value) {
  xml_node n = parent.append_child(name);
  if (!value.empty()) n.text().set(value.c_str());
}

void add_devicenet_values(xml_node parent, const char* name,
                          const std::vector<DevicenetValue>& values) {
  xml_node list = parent.append_child(name);
  for (const auto& v : values) {
    xml_node vn = list.append_child("value");
    vn.append_attribute("motor") = detail::devicenet_motor_text(v.motor).c_str();
    vn.append_attribute("command") = detail::command_hex(v.command).c_str();
    vn.append_attribute("raw") = static_cast<unsigned>(v.raw);
    if (!v.name.empty()) vn.append_attribute("name") = v.name.c_str();
    if (!v.scaled.empty()) vn.append_attribute("scaled") = v.scaled.c_str();
    if (!v.unit.empty()) vn.append_attribute("unit") = v.unit.c_str();
  }
}

void add_devicenet(xml_node root, const DevicenetSection& dn) {
  xml_node n = root.append_child("devicenet");
  n.append_attribute("can_bitrate") = dn.can_bitrate;
  std::string motors;
  for (int m : dn.motors) motors += (motors.empty() ? "" : " ") + detail::devicenet_motor_text(m);
  n.append_attribute("motors") = motors.c_str();
  xml_node modules = n.append_child("io_modules");
  for (const auto& m : dn.io_modules) modules.append_child("module").text().set(m.c_str());
  add_devicenet_values(n, "values", dn.values);
  add_devicenet_values(n, "live", dn.live);
}

struct StringWriter : pugi::xml_writer {
  std::string out;
  void write(const void* data, std::size_t size) override {
    out.append(static_cast<const char*>(data), size);
  }
};

}  // namespace

Result<DriveConfig> read_xml(std::string_view text, std::string_view name) {
  pugi::xml_document doc;
  auto res = doc.load_buffer(text.data(), text.size(), kParseFlags, pugi::encoding_utf8);
  if (!res) {
    const auto off = res.offset < 0 ? std::size_t{0} : static_cast<std::size_t>(res.offset);
    const auto pos = text_position(text, off);
    return Error(Errc::parse_error, std::string(name) + ":" + std::to_string(pos.line) + ":" +
                                        std::to_string(pos.column) +
                                        ": XML syntax error: " + res.description());
  }
  Reader r(name);
  return r.read_document(doc);
}

Result<DriveConfig> read_xml_file(const std::filesystem::path& path) {
  LMCFG_ASSIGN_OR_RETURN(auto text, read_text_file(path));
  return read_xml(text, path.string());
}

Result<std::string> write_xml(const DriveConfig& in, const WriteOptions& opts) {
  LMCFG_TRY(validate(in));
  DriveConfig cfg = in;
  canonicalize(cfg);
  pugi::xml_document doc;
  auto decl = doc.append_child(pugi::node_declaration);
  decl.append_attribute("version") = "1.0";
  decl.append_attribute("encoding") = "UTF-8";
  xml_node root = doc.append_child("lmcfg");
  root.append_attribute("format") = std::string(kFormatId).c_str();
  root.append_attribute("format_version") = kFormatVersion;

  {
    const auto& id = cfg.identity;
    xml_node n = root.append_child("identity");
    text_child(n, "macid", id.macid);
    xml_node link = n.append_child("link");
    link.append_attribute("port") = id.link.port.c_str();
    link.append_attribute("baud") = id.link.baud.c_str();
    link.append_attribute("parity") = id.link.parity.c_str();
    link.append_attribute("stop_bits") = id.link.stop_bits.c_str();
    link.append_attribute("checksum") = id.link.checksum.c_str();
    text_child(n, "product", id.product);
    text_child(n, "firmware", id.firmware);
    text_child(n, "upid_fingerprint", id.upid_fingerprint);
    text_child(n, "tool_version", id.tool_version);
    xml_node db = n.append_child("upid_db");
    db.append_attribute("version") = id.upid_db_version.c_str();
    db.append_attribute("hash") = id.upid_db_hash.c_str();
    text_child(n, "captured_at", id.captured_at);
    xml_node labels = n.append_child("labels");
    for (const auto& [k, v] : id.labels) {
      xml_node l = labels.append_child("label");
      l.append_attribute("key") = k.c_str();
      if (!v.empty()) l.text().set(v.c_str());
    }
  }
  {
    xml_node s = root.append_child("scope");
    std::string layers;
    for (int l = 1; l <= lmcfg::layers::kCount; ++l)
      if (cfg.scope.layers[static_cast<std::size_t>(l - 1)])
        layers += (layers.empty() ? "" : " ") + std::to_string(l);
    s.append_attribute("layers") = layers.c_str();
    s.append_attribute("parameters") = std::string(to_string(cfg.scope.parameters)).c_str();
    s.append_attribute("curves") = cfg.scope.curves ? "true" : "false";
    s.append_attribute("command_table") = cfg.scope.command_table ? "true" : "false";
  }
  {
    xml_node ps = root.append_child("parameters");
    for (int l = 1; l <= lmcfg::layers::kCount; ++l) {
      xml_node ln = ps.append_child("layer");
      ln.append_attribute("number") = l;
      ln.append_attribute("name") = std::string(lmcfg::layers::name(l)).c_str();
      for (const auto& p : cfg.layer(l)) {
        xml_node pn = ln.append_child("param");
        pn.append_attribute("upid") = detail::upid_hex(p.upid).c_str();
        pn.append_attribute("value") = p.value;
        if (p.type) pn.append_attribute("type") = static_cast<unsigned>(*p.type);
        if (p.default_value) pn.append_attribute("default") = *p.default_value;
        if (!p.name.empty()) pn.append_attribute("name") = p.name.c_str();
        if (!p.scaled.empty()) pn.append_attribute("scaled") = p.scaled.c_str();
        if (!p.unit.empty()) pn.append_attribute("unit") = p.unit.c_str();
      }
    }
  }
  {
    xml_node cs = root.append_child("curves");
    for (const auto& c : cfg.curves) {
      xml_node cn = cs.append_child("curve");
      cn.append_attribute("id") = c.id;
      add_rows(cn, "info", c.info);
      add_rows(cn, "data", c.data);
      if (!opts.include_decoded) continue;
      auto v = decode_curve(c);
      if (!v.ok()) continue;
      xml_node d = cn.append_child("decoded");
      d.append_attribute("name") = v->name.c_str();
      d.append_attribute("object_type") = detail::upid_hex(v->object_type).c_str();
      d.append_attribute("x") = std::string(CurveView::x_name(v->x_code)).c_str();
      d.append_attribute("y") = std::string(CurveView::y_name(v->y_code)).c_str();
      d.append_attribute("setpoint_count") = static_cast<unsigned>(v->setpoint_count);
      d.append_attribute("bytes_per_setpoint") = static_cast<unsigned>(v->bytes_per_setpoint);
      d.append_attribute("curve_id") = static_cast<unsigned>(v->curve_id);
      d.append_attribute("length") = v->length;
      d.append_attribute("length_ms") = v->length_ms_text().c_str();
      d.append_attribute("x_dimension") = static_cast<unsigned>(v->x_dimension);
      d.append_attribute("y_dimension") = static_cast<unsigned>(v->y_dimension);
      d.append_attribute("wizard") = detail::upid_hex(v->wizard).c_str();
      std::string wp;
      for (auto w : v->wizard_params) wp += (wp.empty() ? "" : " ") + std::to_string(w);
      d.append_attribute("wizard_params") = wp.c_str();
      for (auto sp : v->setpoints)
        d.append_child("setpoint").text().set(std::to_string(sp).c_str());
    }
  }
  {
    xml_node ts = root.append_child("command_table");
    for (const auto& e : cfg.ct_entries) {
      xml_node en = ts.append_child("entry");
      en.append_attribute("id") = e.id;
      add_rows(en, "raw", e.raw);
      if (!opts.include_decoded) continue;
      xml_node d = en.append_child("decoded");
      d.append_attribute("name") = ct_entry_name(e.raw).c_str();
      auto v = opts.ct_decoder ? opts.ct_decoder->decode(e.id, e.raw) : std::nullopt;
      if (!v) continue;
      d.append_attribute("summary") = v->summary.c_str();
      for (const auto& p : v->params) {
        xml_node pn = d.append_child("param");
        pn.append_attribute("name") = p.name.c_str();
        pn.append_attribute("value") = p.value.c_str();
        if (!p.unit.empty()) pn.append_attribute("unit") = p.unit.c_str();
      }
    }
  }
  if (cfg.devicenet) add_devicenet(root, *cfg.devicenet);
  StringWriter w;
  doc.save(w, "  ", pugi::format_indent, pugi::encoding_utf8);
  return std::move(w.out);
}

Result<void> write_xml_file(const DriveConfig& cfg, const std::filesystem::path& path,
                            const WriteOptions& opts) {
  LMCFG_ASSIGN_OR_RETURN(auto text, write_xml(cfg, opts));
  return write_file_atomic(path, text);
}

}  // namespace lmcfg::config
