#include "config/xml_io.hpp"

#include <pugixml.hpp>
#include <utility>

#include "common/layers.hpp"
#include "config/atomic_file.hpp"
#include "config/io_common.hpp"
#include "config/json_io.hpp"  // text_position
#include "config/migrate.hpp"
#include "config/xml_fields.hpp"

namespace lmcfg::config {
namespace {

using detail::node_path;
using detail::XmlReader;
using pugi::xml_node;

constexpr unsigned kParseFlags =
    pugi::parse_cdata | pugi::parse_escapes | pugi::parse_eol | pugi::parse_ws_pcdata_single;

// The index-th child element `name` of n (null when there is none).
xml_node nth(xml_node n, const char* name, std::size_t index) {
  for (xml_node c : n.children(name))
    if (index-- == 0) return c;
  return {};
}

// The XPath-like location of a validation issue of the model; `layers` are
// the <layer> elements by number.
std::string issue_path(const Issue& is, xml_node root,
                       const std::array<xml_node, lmcfg::layers::kCount>& layers) {
  switch (is.where) {
    case Issue::Where::identity: {
      const xml_node identity = root.child("identity");
      const std::string base = identity ? node_path(identity) : "/lmcfg/identity";
      const std::string& f = is.field;
      if (f.rfind("labels.", 0) == 0) {
        const xml_node labels = identity.child("labels");
        std::string path = labels ? node_path(labels) : base + "/labels";
        for (xml_node l : labels.children("label"))
          if (f.substr(7) == l.attribute("key").value()) path = node_path(l);
        return path;
      }
      if (auto dot = f.find('.'); dot != std::string::npos)
        return base + "/" + f.substr(0, dot) + "/@" + f.substr(dot + 1);
      return base + "/" + f;
    }
    case Issue::Where::scope:
      return node_path(root.child("scope")) + "/@" + is.field;
    case Issue::Where::layer: {
      xml_node ln = layers[static_cast<std::size_t>(is.layer - 1)];
      return ln ? node_path(ln) : node_path(root.child("parameters"));
    }
    case Issue::Where::param:
      return node_path(nth(layers[static_cast<std::size_t>(is.layer - 1)], "param", is.index)) +
             "/@" + is.field;
    case Issue::Where::curve:
    case Issue::Where::ct_entry: {
      const bool curve = is.where == Issue::Where::curve;
      xml_node n =
          nth(root.child(curve ? "curves" : "command_table"), curve ? "curve" : "entry", is.index);
      return is.field == "id" ? node_path(n) + "/@id" : node_path(n.child(is.field.c_str()));
    }
    case Issue::Where::devicenet: {
      const xml_node dn = root.child("devicenet");
      const xml_node modules = dn.child("io_modules");
      return is.field == "io_modules" ? node_path(modules ? modules : dn)
                                      : node_path(dn) + "/@" + is.field;
    }
    case Issue::Where::devicenet_value:
      return node_path(nth(root.child("devicenet").child(is.live ? "live" : "values"), "value",
                           is.index)) +
             "/@" + is.field;
  }
  return "/";
}

// parameters (required): one <layer> per layer around the table's fields.
Result<void> read_parameters(const XmlReader& r, xml_node root, DriveConfig& cfg,
                             std::array<xml_node, lmcfg::layers::kCount>& layers) {
  LMCFG_ASSIGN_OR_RETURN(xml_node params, r.single(root, "parameters", true));
  LMCFG_TRY(r.shape(params, {}, {"layer"}));
  for (xml_node ln : params.children("layer")) {
    LMCFG_TRY(r.shape(ln, {"number", "name"}, {"param"}));
    LMCFG_ASSIGN_OR_RETURN(auto l, r.uint_attr(ln, "number", 4, "a layer number"));
    if (l < 1)
      return r.err_attr(Errc::parse_error, ln, "number",
                        "expected a layer number (1..4), found \"0\"");
    const auto li = static_cast<std::size_t>(l - 1);
    if (layers[li])
      return r.err_attr(Errc::validation_failed, ln, "number",
                        "layer " + std::to_string(l) + " appears twice");
    layers[li] = ln;
    auto& out = cfg.layer(static_cast<int>(l));
    for (xml_node pn : ln.children("param")) {
      Parameter prm;
      LMCFG_TRY(r.read_record(pn, fields::parameter_fields(), prm));
      out.push_back(std::move(prm));
    }
  }
  return {};
}

// curves, command_table (optional): a list element of records, each with an
// optional <decoded> (derived: not read).
template <class R>
Result<void> read_records(const XmlReader& r, xml_node root, const char* list, const char* item,
                          std::span<const fields::Field<R>> table, std::vector<R>& out) {
  LMCFG_ASSIGN_OR_RETURN(xml_node ln, r.single(root, list, false));
  if (!ln) return {};
  LMCFG_TRY(r.shape(ln, {}, {item}));
  for (xml_node n : ln.children(item)) {
    R rec;
    LMCFG_TRY(r.read_record(n, table, rec, {"decoded"}));
    LMCFG_TRY(r.single(n, "decoded", false));
    out.push_back(std::move(rec));
  }
  return {};
}

// Versions 2 and 3: a version 2 file is a version 3 file without <devicenet>.
Result<DriveConfig> read_v2(const XmlReader& r, xml_node root, std::int64_t version) {
  if (xml_node dn = root.child("devicenet"); dn && version < 3)
    return r.err(Errc::parse_error, dn,
                 "unexpected element; the devicenet section is new in format_version 3, this "
                 "file says " +
                     std::to_string(version));
  LMCFG_TRY(r.shape(root, {"format", "format_version"},
                    {"identity", "scope", "parameters", "curves", "command_table", "devicenet"}));
  DriveConfig cfg;
  LMCFG_ASSIGN_OR_RETURN(xml_node identity, r.single(root, "identity", false));
  if (identity) LMCFG_TRY(r.read_record(identity, fields::identity_fields(), cfg.identity));
  LMCFG_ASSIGN_OR_RETURN(xml_node scope, r.single(root, "scope", true));
  LMCFG_TRY(r.read_record(scope, fields::scope_fields(), cfg.scope));
  std::array<xml_node, lmcfg::layers::kCount> layers{};
  LMCFG_TRY(read_parameters(r, root, cfg, layers));
  LMCFG_TRY(read_records(r, root, "curves", "curve", fields::curve_fields(), cfg.curves));
  LMCFG_TRY(
      read_records(r, root, "command_table", "entry", fields::ct_entry_fields(), cfg.ct_entries));
  LMCFG_ASSIGN_OR_RETURN(xml_node dnn, r.single(root, "devicenet", false));
  if (dnn) {
    DevicenetSection dn;
    LMCFG_TRY(r.read_record(dnn, fields::devicenet_fields(), dn));
    cfg.devicenet = std::move(dn);
  }
  if (auto is = find_issue(cfg))
    return Error(Errc::validation_failed,
                 r.name() + ": " + issue_path(*is, root, layers) + ": " + is->message);
  canonicalize(cfg);
  return cfg;
}

Result<DriveConfig> read_document(XmlReader& r, const pugi::xml_document& doc) {
  xml_node root = doc.document_element();
  if (!root || std::string_view(root.name()) != "lmcfg")
    return Error(Errc::parse_error, r.name() + ": " + (root ? node_path(root) : std::string("/")) +
                                        ": expected the root element <lmcfg>");
  LMCFG_ASSIGN_OR_RETURN(auto fmt, r.attr(root, "format", true));
  LMCFG_TRY(detail::check_format_id(fmt, r.where(root) + "/@format"));
  LMCFG_ASSIGN_OR_RETURN(auto version,
                         r.int_attr(root, "format_version", "an integer format version"));
  LMCFG_TRY(detail::check_format_version(version, r.name(), r.where(root) + "/@format_version"));
  r.set_version(version);
  if (version == 1) {
    LMCFG_ASSIGN_OR_RETURN(auto v1, detail::read_xml_v1(r, root));
    return migrate_v1_to_v2(v1);
  }
  return read_v2(r, root, version);
}

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
  XmlReader r(name);
  return read_document(r, doc);
}

Result<DriveConfig> read_xml_file(const std::filesystem::path& path) {
  LMCFG_ASSIGN_OR_RETURN(auto text, read_text_file(path));
  return read_xml(text, path.string());
}

}  // namespace lmcfg::config
