// Writing the canonical XML form: the document's frame around the records of
// the field tables (xml_fields.hpp), and the decoded views.
#include <pugixml.hpp>

#include "common/layers.hpp"
#include "config/atomic_file.hpp"
#include "config/io_common.hpp"
#include "config/xml_fields.hpp"
#include "config/xml_io.hpp"

namespace lmcfg::config {
namespace {

using detail::write_record;
using pugi::xml_node;

struct StringWriter : pugi::xml_writer {
  std::string out;
  void write(const void* data, std::size_t size) override {
    out.append(static_cast<const char*>(data), size);
  }
};

// <parameters>: one <layer> per layer, every layer (empty ones too).
void add_parameters(xml_node root, const DriveConfig& cfg) {
  xml_node ps = root.append_child("parameters");
  for (int l = 1; l <= lmcfg::layers::kCount; ++l) {
    xml_node ln = ps.append_child("layer");
    ln.append_attribute("number") = l;
    ln.append_attribute("name") = std::string(lmcfg::layers::name(l)).c_str();
    for (const auto& p : cfg.layer(l))
      write_record(ln.append_child("param"), fields::parameter_fields(), p);
  }
}

// A curve's decoded view (derived; ignored on read).
void add_curve_view(xml_node cn, const CurveView& v) {
  xml_node d = cn.append_child("decoded");
  d.append_attribute("name") = v.name.c_str();
  d.append_attribute("object_type") = detail::upid_hex(v.object_type).c_str();
  d.append_attribute("x") = std::string(CurveView::x_name(v.x_code)).c_str();
  d.append_attribute("y") = std::string(CurveView::y_name(v.y_code)).c_str();
  d.append_attribute("setpoint_count") = static_cast<unsigned>(v.setpoint_count);
  d.append_attribute("bytes_per_setpoint") = static_cast<unsigned>(v.bytes_per_setpoint);
  d.append_attribute("curve_id") = static_cast<unsigned>(v.curve_id);
  d.append_attribute("length") = v.length;
  d.append_attribute("length_ms") = v.length_ms_text().c_str();
  d.append_attribute("x_dimension") = static_cast<unsigned>(v.x_dimension);
  d.append_attribute("y_dimension") = static_cast<unsigned>(v.y_dimension);
  d.append_attribute("wizard") = detail::upid_hex(v.wizard).c_str();
  std::string wp;
  for (auto w : v.wizard_params) wp += (wp.empty() ? "" : " ") + std::to_string(w);
  d.append_attribute("wizard_params") = wp.c_str();
  for (auto sp : v.setpoints) d.append_child("setpoint").text().set(std::to_string(sp).c_str());
}

void add_curves(xml_node root, const std::vector<Curve>& curves, const WriteOptions& opts) {
  xml_node cs = root.append_child("curves");
  for (const auto& c : curves) {
    xml_node cn = cs.append_child("curve");
    write_record(cn, fields::curve_fields(), c);
    if (!opts.include_decoded) continue;
    if (auto v = decode_curve(c); v.ok()) add_curve_view(cn, *v);
  }
}

// A command table entry's decoded view (derived; ignored on read).
void add_ct_entry_view(xml_node en, const CtEntry& e, const WriteOptions& opts) {
  xml_node d = en.append_child("decoded");
  d.append_attribute("name") = ct_entry_name(e.raw).c_str();
  auto v = opts.ct_decoder ? opts.ct_decoder->decode(e.id, e.raw) : std::nullopt;
  if (!v) return;
  d.append_attribute("summary") = v->summary.c_str();
  for (const auto& p : v->params) {
    xml_node pn = d.append_child("param");
    pn.append_attribute("name") = p.name.c_str();
    pn.append_attribute("value") = p.value.c_str();
    if (!p.unit.empty()) pn.append_attribute("unit") = p.unit.c_str();
  }
}

void add_command_table(xml_node root, const std::vector<CtEntry>& entries,
                       const WriteOptions& opts) {
  xml_node ts = root.append_child("command_table");
  for (const auto& e : entries) {
    xml_node en = ts.append_child("entry");
    write_record(en, fields::ct_entry_fields(), e);
    if (opts.include_decoded) add_ct_entry_view(en, e, opts);
  }
}

}  // namespace

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
  write_record(root.append_child("identity"), fields::identity_fields(), cfg.identity);
  write_record(root.append_child("scope"), fields::scope_fields(), cfg.scope);
  add_parameters(root, cfg);
  add_curves(root, cfg.curves, opts);
  add_command_table(root, cfg.ct_entries, opts);
  if (cfg.devicenet)
    write_record(root.append_child("devicenet"), fields::devicenet_fields(), *cfg.devicenet);
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
