// The commands' --json reports (report/json_reports.hpp). Member names and
// their order are the contract of docs/json-reports.md: tests compare them.
#include "report/json_reports.hpp"

#include <cstdio>

#include "common/bytes.hpp"
#include "common/layers.hpp"
#include "db/value.hpp"
#include "link/session.hpp"
#include "ops/backup.hpp"
#include "ops/devicenet.hpp"
#include "ops/devicenet_restore.hpp"
#include "transport/transport.hpp"

namespace lmcfg::report {
namespace {

std::size_t parameter_count(const config::DriveConfig& cfg) {
  std::size_t n = 0;
  for (const auto& l : cfg.layers) n += l.size();
  return n;
}

}  // namespace

Json backup_json(const std::string& file, const config::DriveConfig& cfg, std::uint64_t telegrams) {
  return Json{{"file", file},
              {"parameters", parameter_count(cfg)},
              {"curves", cfg.curves.size()},
              {"ct_entries", cfg.ct_entries.size()},
              {"telegrams", telegrams}};
}

Json devicenet_backup_json(const std::string& file, const config::DriveConfig& cfg) {
  const auto& dn = *cfg.devicenet;
  return Json{{"file", file},
              {"devicenet_macid", cfg.identity.macid},
              {"motors", dn.motors.size()},
              {"values", dn.values.size()},
              {"live", dn.live.size()},
              {"runtime_note", ops::kRuntimeNote}};
}

Json convert_json(const std::string& input, const std::string& output, config::FileFormat format,
                  std::size_t bytes, const config::DriveConfig& cfg, bool ct_decoded) {
  Json j{{"input", input},
         {"output", output},
         {"format", std::string(config::to_string(format))},
         {"format_version", config::kFormatVersion},
         {"bytes", bytes},
         {"parameters", parameter_count(cfg)},
         {"curves", cfg.curves.size()},
         {"ct_entries", cfg.ct_entries.size()},
         {"ct_decoded", ct_decoded}};
  if (cfg.devicenet) {
    j["devicenet_values"] = cfg.devicenet->values.size();
    j["devicenet_live"] = cfg.devicenet->live.size();
  }
  return j;
}

Json restore_json(const ops::RestoreOutcome& out, const std::string& file) {
  Json j;
  j["file"] = file;
  j["outcome"] = ops::outcome_name(out);
  if (out.relink)
    j["link_after"] = {{"changed", out.relink->changed},
                       {"summary", out.relink->summary},
                       {"reasons", out.relink->reasons}};
  // Named: alive while its items are copied.
  const Json plan =
      out.devicenet ? ops::devicenet_plan_json(*out.devicenet) : ops::plan_json(out.plan);
  for (const auto& [k, v] : plan.items()) j[k] = v;
  if (out.second_pass) j["second_pass"] = ops::plan_json(*out.second_pass)["steps"];
  j["mismatches"] = out.mismatches;
  if (!out.unacknowledged.empty()) j["unacknowledged"] = out.unacknowledged;
  if (out.undo) j["undo"] = undo_json(*out.undo);
  if (out.error) j["error"] = out.error->message;
  return j;
}

Json restore_steps_json(const ops::RestoreOutcome& out) {
  if (out.devicenet) {
    Json steps = ops::devicenet_plan_json(*out.devicenet)["steps"];
    for (auto& s : steps) {
      s.erase("name");
      s["old"] = Json(s["old"]["raw"]);
      s["new"] = Json(s["new"]["raw"]);
    }
    return steps;
  }
  Json steps = ops::plan_json(out.plan)["steps"];
  if (out.second_pass) {
    // Named: a range-for over a member of a temporary would read freed memory.
    const Json second = ops::plan_json(*out.second_pass);
    for (const auto& s : second["steps"]) steps.push_back(s);
  }
  return steps;
}

Json undo_json(const ops::UndoSaved& u) {
  return {{"path", u.path.string()}, {"command", u.command}};
}

Json undo_list_json(const std::filesystem::path& dir, const std::vector<ops::UndoEntry>& records) {
  Json j;
  j["dir"] = dir.string();
  j["records"] = Json::array();
  for (const auto& r : records)
    j["records"].push_back({{"drive", r.drive},
                            {"time", r.time},
                            {"command", r.command},
                            {"path", r.path.string()},
                            {"holds", r.holds}});
  return j;
}

Json default_json(const char* outcome, const ops::DefaultReport* rep, const db::Database& db,
                  const std::string& error) {
  Json j;
  j["outcome"] = outcome;
  j["steps"] = rep ? rep->done : std::vector<std::string>{};
  j["kept"] = Json::array();
  if (rep) {
    for (const auto& k : rep->kept) {
      j["kept"].push_back(
          {{"upid", hex(k.upid, 4)},
           {"value", {{"raw", k.value}, {"display", ops::display_value(db, k.upid, k.value)}}}});
    }
    j["recovered"] = rep->recovered;
    j["recovery"] = rep->recovery_note;
    j["link_may_change"] = rep->link_may_change;
    if (rep->undo) j["undo"] = undo_json(*rep->undo);
  }
  if (!error.empty()) j["error"] = error;
  return j;
}

Json default_steps_json(const ops::DefaultOptions& d, const ops::DefaultReport* rep,
                        const db::Database& db) {
  Json steps = Json::array();
  auto add = [&](Json o) {
    Json step{{"step", steps.size() + 1}};
    for (auto& [k, v] : o.items()) step[k] = v;
    steps.push_back(std::move(step));
  };
  for (int layer = lmcfg::layers::kOS; layer <= lmcfg::layers::kAppl; ++layer)
    if (d.layers[static_cast<std::size_t>(layer - 1)])
      add({{"action", "default_layer"}, {"layer", std::string(lmcfg::layers::name(layer))}});
  if (d.curves) add({{"action", "delete_all_curves"}});
  if (d.command_table) add({{"action", "delete_all_ct"}});
  if (rep) {
    for (const auto& k : rep->kept)
      add({{"action", "write_rom"},
           {"upid", hex(k.upid, 4)},
           {"new", {{"raw", k.value}, {"display", ops::display_value(db, k.upid, k.value)}}},
           {"why", "kept communication value"}});
  }
  return steps;
}

Json journal_json(const std::filesystem::path& journal, const std::vector<Json>& records) {
  Json j;
  j["journal"] = journal.string();
  j["records"] = records;
  return j;
}

Json link_settings_json(const ops::LinkState& st) {
  auto arr = Json::array();
  for (std::size_t i = 0; i < ops::kLinkSettings; ++i) {
    const auto s = static_cast<ops::LinkSetting>(i);
    const auto& v = st.values[i];
    Json j;
    j["setting"] = ops::setting_key(s);
    j["upid"] = v.upid ? Json(hex(*v.upid, 4)) : Json();
    j["rom"] = v.rom ? Json(*v.rom) : Json();
    j["value"] = v.text;
    j["note"] = v.note;
    arr.push_back(std::move(j));
  }
  return arr;
}

Json link_json(const std::string& port, const ops::LinkState& now) {
  Json j;
  j["drive"] = hex(now.in_use.macid, 2);
  j["port"] = port;
  j["link_options"] = link::link_options_of(now.in_use);
  j["settings"] = link_settings_json(now);
  return j;
}

void add_link_plan(Json& j, const ops::LinkPlan& plan) {
  j["plan"] = Json::array();
  for (const auto& w : plan.writes) j["plan"].push_back(w.text);
  j["new_link_options"] = link::link_options_of(plan.after);
}

void add_link_changed(Json& j, const ops::LinkApplyReport& rep) {
  j["outcome"] = "changed";
  j["found"] = rep.relink.summary;
  j["scanned"] = rep.scanned;
  j["new_link_options"] = link::link_options_of(rep.relink.used);
  j["settings_after"] = link_settings_json(rep.after);
}

Json param_json(std::uint16_t upid, const db::Parameter* d, const db::ValueSpec& spec,
                const char* where, std::uint32_t value, const std::string& text,
                const std::optional<ops::UndoSaved>& undo) {
  Json j;
  j["upid"] = hex(upid, 4);
  j["name"] = d ? d->name : "";
  j["type"] = spec.type ? std::string(db::type_name(*spec.type)) : "";
  j["memory"] = where;
  j["raw"] = value;
  j["raw_hex"] = hex(value, 8);
  // The field as a number of its type (signed types sign-extended); null
  // when the type is unknown, a text type, or the field does not fit it.
  std::optional<std::int64_t> integer;
  if (spec.type && !db::is_text_type(*spec.type) && *spec.type != db::TypeCode::LinFloat)
    integer = db::field_integer(*spec.type, value);
  j["integer"] = integer ? Json(*integer) : Json(nullptr);
  j["unit"] = spec.unit;
  j["value"] = text;
  if (undo) j["undo"] = undo_json(*undo);
  return j;
}

Json param_write_step_json(const char* action, std::uint16_t upid, const db::Parameter* d,
                           const db::ValueSpec& spec, std::optional<std::uint32_t> old,
                           std::uint32_t value) {
  const bool known = spec.type || !spec.labels.empty();
  auto shown = [&](std::uint32_t v) {
    return Json{{"raw", v}, {"display", known ? db::format_value(spec, v) : std::to_string(v)}};
  };
  return Json{{"step", 1},
              {"action", action},
              {"upid", hex(upid, 4)},
              {"name", d ? d->name : ""},
              {"old", old ? shown(*old) : Json(nullptr)},
              {"new", shown(value)}};
}

nlohmann::json scan_json(const link::ScanReport& r) {
  nlohmann::json j;
  j["found"] = nlohmann::json::array();
  for (const auto& d : r.found) {
    j["found"].push_back({{"id", d.id},
                          {"baud", d.line.baud},
                          {"parity", std::string(transport::parity_name(d.line.parity))},
                          {"stop_bits", d.line.stop_bits},
                          {"checksum", link::checksum_name(d.checksum)},
                          {"response_bytes", d.response_bytes},
                          {"options", link::link_options_of(d)},
                          {"how", d.how}});
  }
  j["passes"] = nlohmann::json::array();
  for (const auto& p : r.passes) {
    j["passes"].push_back({{"line", transport::format_settings(p.line)},
                           {"checksum", link::checksum_name(p.checksum)},
                           {"ids", p.ids},
                           {"deadline_ms", p.deadline_ms},
                           {"seconds", p.seconds}});
  }
  j["notes"] = r.notes;
  j["seconds"] = r.seconds;
  j["telegrams"] = r.telegrams;
  return j;
}

nlohmann::json linudp_scan_json(const link::LinudpScanReport& r) {
  nlohmann::json j;
  j["port"] = r.port;
  j["addresses"] = nlohmann::json::array();
  for (const auto& a : r.addresses) {
    nlohmann::json e{{"host", a.host},
                     {"answer", a.answer == link::LinudpAnswer::answered ? "answered"
                                : a.answer == link::LinudpAnswer::held   ? "held_by_other_master"
                                                                         : "silent"},
                     {"ms", a.ms},
                     {"datagrams", a.datagrams}};
    auto word = [&](const char* key, std::optional<std::uint16_t> v) {
      if (v) e[key] = hex(*v, 4, "h");
    };
    word("state_var", a.state_var);
    word("status_word", a.status_word);
    word("error_code", a.error_code);
    if (a.firmware) e["firmware"] = hex(*a.firmware, 4, "h");
    if (!a.firmware_note.empty()) e["firmware_note"] = a.firmware_note;
    j["addresses"].push_back(std::move(e));
  }
  j["seconds"] = r.seconds;
  j["datagrams"] = r.datagrams;
  return j;
}

}  // namespace lmcfg::report
