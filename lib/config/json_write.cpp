// Writing the canonical JSON form (split from json_io.cpp: reading there).
#include <nlohmann/json.hpp>

#include "common/layers.hpp"
#include "config/atomic_file.hpp"
#include "config/io_common.hpp"
#include "config/json_io.hpp"

namespace lmcfg::config {

using ojson = nlohmann::ordered_json;

namespace {

ojson rows_json(ByteView b) {
  ojson a = ojson::array();
  for (auto& r : detail::block_rows(b)) a.push_back(std::move(r));
  return a;
}

ojson devicenet_values_json(const std::vector<DevicenetValue>& values) {
  ojson a = ojson::array();
  for (const auto& v : values) {
    ojson j;
    j["motor"] = detail::devicenet_motor_text(v.motor);
    j["command"] = detail::command_hex(v.command);
    j["raw"] = v.raw;
    if (!v.name.empty()) j["name"] = v.name;
    if (!v.scaled.empty()) j["scaled"] = v.scaled;
    if (!v.unit.empty()) j["unit"] = v.unit;
    a.push_back(std::move(j));
  }
  return a;
}

ojson devicenet_json(const DevicenetSection& dn) {
  ojson d;
  d["can_bitrate"] = dn.can_bitrate;
  d["io_modules"] = dn.io_modules;
  ojson motors = ojson::array();
  for (int m : dn.motors) motors.push_back(detail::devicenet_motor_text(m));
  d["motors"] = std::move(motors);
  d["values"] = devicenet_values_json(dn.values);
  d["live"] = devicenet_values_json(dn.live);
  return d;
}

}  // namespace

Result<std::string> write_json(const DriveConfig& in, const WriteOptions& opts) {
  LMCFG_TRY(validate(in));
  DriveConfig cfg = in;
  canonicalize(cfg);
  ojson doc;
  doc["format"] = kFormatId;
  doc["format_version"] = kFormatVersion;
  {
    const auto& id = cfg.identity;
    ojson j;
    j["macid"] = id.macid;
    j["link"] = ojson{{"port", id.link.port},
                      {"baud", id.link.baud},
                      {"parity", id.link.parity},
                      {"stop_bits", id.link.stop_bits},
                      {"checksum", id.link.checksum}};
    j["product"] = id.product;
    j["firmware"] = id.firmware;
    j["upid_fingerprint"] = id.upid_fingerprint;
    j["tool_version"] = id.tool_version;
    j["upid_db"] = ojson{{"version", id.upid_db_version}, {"hash", id.upid_db_hash}};
    j["captured_at"] = id.captured_at;
    ojson labels = ojson::object();
    for (const auto& [k, v] : id.labels) labels[k] = v;  // std::map: sorted
    j["labels"] = std::move(labels);
    doc["identity"] = std::move(j);
  }
  {
    ojson s;
    ojson layers = ojson::array();
    for (int l = 1; l <= lmcfg::layers::kCount; ++l)
      if (cfg.scope.layers[static_cast<std::size_t>(l - 1)]) layers.push_back(l);
    s["layers"] = std::move(layers);
    s["parameters"] = to_string(cfg.scope.parameters);
    s["curves"] = cfg.scope.curves;
    s["command_table"] = cfg.scope.command_table;
    doc["scope"] = std::move(s);
  }
  {
    ojson params = ojson::array();
    for (int l = 1; l <= lmcfg::layers::kCount; ++l) {
      ojson lj;
      lj["layer"] = l;
      lj["name"] = lmcfg::layers::name(l);
      ojson arr = ojson::array();
      for (const auto& p : cfg.layer(l)) {
        ojson q;
        q["upid"] = detail::upid_hex(p.upid);
        q["value"] = p.value;
        if (p.type) q["type"] = *p.type;
        if (p.default_value) q["default"] = *p.default_value;
        if (!p.name.empty()) q["name"] = p.name;
        if (!p.scaled.empty()) q["scaled"] = p.scaled;
        if (!p.unit.empty()) q["unit"] = p.unit;
        arr.push_back(std::move(q));
      }
      lj["params"] = std::move(arr);
      params.push_back(std::move(lj));
    }
    doc["parameters"] = std::move(params);
  }
  {
    ojson curves = ojson::array();
    for (const auto& c : cfg.curves) {
      ojson cj;
      cj["id"] = c.id;
      cj["info"] = rows_json(c.info);
      cj["data"] = rows_json(c.data);
      if (opts.include_decoded) {
        if (auto v = decode_curve(c); v.ok()) {
          ojson d;
          d["name"] = v->name;
          d["object_type"] = detail::upid_hex(v->object_type);
          d["x"] = CurveView::x_name(v->x_code);
          d["y"] = CurveView::y_name(v->y_code);
          d["setpoint_count"] = v->setpoint_count;
          d["bytes_per_setpoint"] = v->bytes_per_setpoint;
          d["curve_id"] = v->curve_id;
          d["length"] = v->length;
          d["length_ms"] = v->length_ms_text();
          d["x_dimension"] = v->x_dimension;
          d["y_dimension"] = v->y_dimension;
          d["wizard"] = detail::upid_hex(v->wizard);
          d["wizard_params"] = v->wizard_params;
          d["setpoints"] = v->setpoints;
          cj["decoded"] = std::move(d);
        }
      }
      curves.push_back(std::move(cj));
    }
    doc["curves"] = std::move(curves);
  }
  {
    ojson table = ojson::array();
    for (const auto& e : cfg.ct_entries) {
      ojson ej;
      ej["id"] = e.id;
      ej["raw"] = rows_json(e.raw);
      if (opts.include_decoded) {
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
        ej["decoded"] = std::move(d);
      }
      table.push_back(std::move(ej));
    }
    doc["command_table"] = std::move(table);
  }
  if (cfg.devicenet) doc["devicenet"] = devicenet_json(*cfg.devicenet);
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
