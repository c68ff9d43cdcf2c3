// `lmcfg db ... --json` and `db scan`/`db merge --json` (report/json_reports.hpp):
// the UPID database's rows as JSON. Plain nlohmann::json (members sorted by
// name), as these reports have always been printed.
#include <string>

#include "common/bytes.hpp"
#include "db/value.hpp"
#include "report/json_reports.hpp"

namespace lmcfg::report {

using nlohmann::json;

json db_provenance_json(const db::Provenance& p) {
  return {{"source", p.source}, {"file", p.file}, {"line", p.line}};
}

json db_parameter_json(const db::Parameter& p) {
  json j = {{"upid", hex(p.upid, 4)},
            {"layer", std::string(db::layer_name(p.layer))},
            {"name", p.name},
            {"path", p.path},
            {"profiles", p.profiles.empty() ? json::array({"*"}) : json(p.profiles)},
            {"type", p.spec.type ? json(std::string(db::type_name(*p.spec.type))) : json(nullptr)},
            {"unit", p.spec.unit},
            {"scale", p.spec.scale ? json(*p.spec.scale) : json(nullptr)},
            {"min", p.spec.min ? json(*p.spec.min) : json(nullptr)},
            {"max", p.spec.max ? json(*p.spec.max) : json(nullptr)},
            {"default", p.default_value ? json(*p.default_value) : json(nullptr)},
            {"comm", p.comm},
            {"description", p.description},
            {"provenance", db_provenance_json(p.prov)}};
  if (p.address_usage) {
    const auto& a = *p.address_usage;
    j["address_usage"] = {{"raw", hex(a.raw, 4)},       {"ram_read", a.ram_read()},
                          {"ram_write", a.ram_write()}, {"rom_read", a.rom_read()},
                          {"rom_write", a.rom_write()}, {"no_hash", a.no_hash()}};
  } else {
    j["address_usage"] = nullptr;
  }
  json labels = json::array();
  for (const auto& l : p.spec.labels) labels.push_back({{"raw", l.raw}, {"label", l.label}});
  j["enum"] = labels;
  return j;
}

json db_show_json(std::uint16_t upid, const std::vector<const db::Parameter*>& found) {
  json arr = json::array();
  for (const auto* p : found) arr.push_back(db_parameter_json(*p));
  json out = {{"upid", hex(upid, 4)}, {"known", !found.empty()}, {"definitions", arr}};
  if (found.empty()) out["note"] = "unknown to the database; the drive can be asked";
  return out;
}

json db_parameters_json(const std::vector<const db::Parameter*>& v) {
  json arr = json::array();
  for (const auto* p : v) arr.push_back(db_parameter_json(*p));
  return arr;
}

json db_errors_json(const std::vector<const db::ErrorEntry*>& v) {
  json arr = json::array();
  for (const auto* e : v)
    arr.push_back({{"domain", e->domain},
                   {"code", e->code_text},
                   {"class", e->error_class},
                   {"fatal", e->fatal()},
                   {"text", e->text},
                   {"description", e->description},
                   {"action", e->action},
                   {"provenance", db_provenance_json(e->prov)}});
  return arr;
}

json db_commands_json(const std::vector<db::MotionCommand>& v) {
  json arr = json::array();
  for (const auto& c : v) {
    json params = json::array();
    for (const auto& p : c.params)
      params.push_back(
          {{"index", p.index},
           {"offset", p.offset},
           {"name", p.name},
           {"type", p.spec.type ? json(std::string(db::type_name(*p.spec.type))) : json(nullptr)},
           {"unit", p.spec.unit},
           {"scale", p.spec.scale ? json(*p.spec.scale) : json(nullptr)},
           {"range", p.range_text},
           {"min", p.spec.min ? json(*p.spec.min) : json(nullptr)},
           {"max", p.spec.max ? json(*p.spec.max) : json(nullptr)},
           {"scaled", p.scaled},
           {"provenance", db_provenance_json(p.prov)}});
    arr.push_back({{"header", hex(c.header() >> 4, 3) + "x"},
                   {"master", hex(c.master, 2)},
                   {"sub", hex(c.sub, 1)},
                   {"name", c.name},
                   {"products", c.products},
                   {"parameters", params},
                   {"provenance", db_provenance_json(c.prov)}});
  }
  return arr;
}

json db_value_spec_json(const db::ValueSpec& s) {
  json labels = json::array();
  for (const auto& l : s.labels) labels.push_back({{"raw", l.raw}, {"label", l.label}});
  auto opt = [](const auto& v) { return v ? json(*v) : json(nullptr); };
  return {{"type", s.type ? json(std::string(db::type_name(*s.type))) : json(nullptr)},
          {"min", opt(s.min)},
          {"max", opt(s.max)},
          {"unit", s.unit},
          {"scale", opt(s.scale)},
          {"labels", labels}};
}

json db_devicenet_command_json(const db::DevicenetCommand& c) {
  return {{"id", c.id_text},
          {"direction", c.direction},
          {"name", c.name},
          {"table_name", c.table_name},
          {"range", c.range_text},
          {"unit_text", c.unit_text},
          {"value", db_value_spec_json(c.spec)},
          {"addressed", c.addressed},
          {"direct", c.direct},
          {"description", c.description},
          {"provenance", db_provenance_json(c.prov)}};
}

json db_devicenet_parameters_json(const std::vector<db::DevicenetParameter>& v) {
  json arr = json::array();
  for (const auto& p : v)
    arr.push_back({{"id", p.id},
                   {"name", p.name},
                   {"path", p.path},
                   {"value", db_value_spec_json(p.spec)},
                   {"default", p.default_value ? json(*p.default_value) : json(nullptr)},
                   {"comm", p.comm},
                   {"description", p.description},
                   {"provenance", db_provenance_json(p.prov)}});
  return arr;
}

json db_devicenet_commands_json(const std::vector<db::DevicenetCommand>& v) {
  json arr = json::array();
  for (const auto& c : v) arr.push_back(db_devicenet_command_json(c));
  return arr;
}

json db_info_json(const db::DbInfo& i) {
  json counts = json::object();
  for (const auto& [k, n] : i.counts) counts[k] = n;
  return json{{"path", i.path},
              {"schema_version", i.schema_version},
              {"content_hash", i.content_hash},
              {"built_from", i.built_from},
              {"counts", counts}};
}

json db_scan_json(const std::string& file, const ops::DbScanResult& r, std::uint64_t telegrams,
                  const std::string& merged_into) {
  json j = {{"file", file},
            {"profile", r.profile.id},
            {"source", r.source},
            {"upids", r.rows.size()},
            {"named", r.named},
            {"asked", r.asked},
            {"resumed", r.resumed},
            {"refused", r.refused},
            {"telegrams", telegrams},
            {"layers",
             {{"OS", r.per_layer[0]},
              {"MC", r.per_layer[1]},
              {"Intf", r.per_layer[2]},
              {"Appl", r.per_layer[3]}}}};
  if (!merged_into.empty()) j["merged_into"] = merged_into;
  return j;
}

json db_merge_json(const std::string& into, const ops::MergeReport& m) {
  return json{{"profile", m.profile},
              {"into", into},
              {"parameters_added", m.parameters_added},
              {"parameters_replaced", m.parameters_replaced},
              {"profile_replaced", m.profile_replaced}};
}

}  // namespace lmcfg::report
