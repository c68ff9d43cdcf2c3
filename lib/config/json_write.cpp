// Writing the canonical JSON form: the document's frame around the records
// of the field tables (json_fields.hpp), and the decoded views.
#include <nlohmann/json.hpp>

#include "common/layers.hpp"
#include "config/atomic_file.hpp"
#include "config/io_common.hpp"
#include "config/json_fields.hpp"
#include "config/json_io.hpp"

namespace lmcfg::config {

using detail::ojson;
using detail::write_record;

namespace {

// parameters: one object per layer, every layer (empty ones too).
ojson parameters_json(const DriveConfig& cfg) {
  ojson params = ojson::array();
  for (int l = 1; l <= lmcfg::layers::kCount; ++l) {
    ojson lj;
    lj["layer"] = l;
    lj["name"] = lmcfg::layers::name(l);
    ojson arr = ojson::array();
    for (const auto& p : cfg.layer(l)) arr.push_back(write_record(fields::parameter_fields(), p));
    lj["params"] = std::move(arr);
    params.push_back(std::move(lj));
  }
  return params;
}

// A curve's decoded view (derived; ignored on read).
ojson curve_view_json(const CurveView& v) {
  ojson d;
  d["name"] = v.name;
  d["object_type"] = detail::upid_hex(v.object_type);
  d["x"] = CurveView::x_name(v.x_code);
  d["y"] = CurveView::y_name(v.y_code);
  d["setpoint_count"] = v.setpoint_count;
  d["bytes_per_setpoint"] = v.bytes_per_setpoint;
  d["curve_id"] = v.curve_id;
  d["length"] = v.length;
  d["length_ms"] = v.length_ms_text();
  d["x_dimension"] = v.x_dimension;
  d["y_dimension"] = v.y_dimension;
  d["wizard"] = detail::upid_hex(v.wizard);
  d["wizard_params"] = v.wizard_params;
  d["setpoints"] = v.setpoints;
  return d;
}

ojson curves_json(const std::vector<Curve>& curves, const WriteOptions& opts) {
  ojson out = ojson::array();
  for (const auto& c : curves) {
    ojson cj = write_record(fields::curve_fields(), c);
    if (opts.include_decoded) {
      if (auto v = decode_curve(c); v.ok()) cj["decoded"] = curve_view_json(*v);
    }
    out.push_back(std::move(cj));
  }
  return out;
}

// A command table entry's decoded view (derived; ignored on read).
ojson ct_entry_view_json(const CtEntry& e, const WriteOptions& opts) {
  ojson d;
  d["name"] = ct_entry_name(e.raw);
  if (auto v = opts.ct_decoder ? opts.ct_decoder->decode(e.id, e.raw) : std::nullopt) {
    d["summary"] = v->summary;
    ojson ps = ojson::array();
    for (const auto& p : v->params) {
      ojson pj;
      pj["name"] = p.name;
      pj["value"] = p.value;
      if (!p.unit.empty()) pj["unit"] = p.unit;
      ps.push_back(std::move(pj));
    }
    d["params"] = std::move(ps);
  }
  return d;
}

ojson command_table_json(const std::vector<CtEntry>& entries, const WriteOptions& opts) {
  ojson out = ojson::array();
  for (const auto& e : entries) {
    ojson ej = write_record(fields::ct_entry_fields(), e);
    if (opts.include_decoded) ej["decoded"] = ct_entry_view_json(e, opts);
    out.push_back(std::move(ej));
  }
  return out;
}

}  // namespace

Result<std::string> write_json(const DriveConfig& in, const WriteOptions& opts) {
  LMCFG_TRY(validate(in));
  DriveConfig cfg = in;
  canonicalize(cfg);
  ojson doc;
  doc["format"] = kFormatId;
  doc["format_version"] = kFormatVersion;
  doc["identity"] = write_record(fields::identity_fields(), cfg.identity);
  doc["scope"] = write_record(fields::scope_fields(), cfg.scope);
  doc["parameters"] = parameters_json(cfg);
  doc["curves"] = curves_json(cfg.curves, opts);
  doc["command_table"] = command_table_json(cfg.ct_entries, opts);
  if (cfg.devicenet) doc["devicenet"] = write_record(fields::devicenet_fields(), *cfg.devicenet);
  try {
    return doc.dump(2, ' ', false, ojson::error_handler_t::strict) + "\n";
  } catch (const ojson::exception& e) {
    return Error(Errc::invalid_argument, std::string("cannot write JSON: ") + e.what());
  }
}

Result<void> write_json_file(const DriveConfig& cfg, const std::filesystem::path& path,
                             const WriteOptions& opts) {
  LMCFG_ASSIGN_OR_RETURN(auto text, write_json(cfg, opts));
  return write_file_atomic(path, text);
}

}  // namespace lmcfg::config
