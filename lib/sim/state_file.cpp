#include "sim/state_file.hpp"

#include <cstdio>
#include <filesystem>
#include <fstream>
#include <sstream>
#include <stdexcept>

#include "common/bytes.hpp"
#include "common/families.hpp"
#include "sim/link.hpp"

namespace lmcfg::sim {

using nlohmann::json;

namespace {

struct BadField : std::runtime_error {
  using std::runtime_error::runtime_error;
};

std::string hex16(unsigned v) {
  char b[8];
  std::snprintf(b, sizeof b, "%04X", v & 0xFFFF);
  return b;
}
std::string hex8(unsigned v) {
  char b[8];
  std::snprintf(b, sizeof b, "%02X", v & 0xFF);
  return b;
}

// Numbers: JSON integers (negative ones as two's complement) or strings
// ("13A2", "0x13A2", "13A2h": hex).
std::uint32_t num(const json& v, const char* what) {
  if (v.is_number_unsigned()) {
    const auto u = v.get<std::uint64_t>();
    if (u > 0xFFFFFFFFull) throw BadField(std::string(what) + ": value out of 32-bit range");
    return static_cast<std::uint32_t>(u);
  }
  if (v.is_number_integer()) {
    const auto i = v.get<std::int64_t>();
    if (i < INT32_MIN || i > static_cast<std::int64_t>(UINT32_MAX))
      throw BadField(std::string(what) + ": out of range");
    return static_cast<std::uint32_t>(static_cast<std::int32_t>(i));
  }
  if (v.is_string()) {
    auto n = parse_number(v.get<std::string>(), true);
    if (!n) throw BadField(std::string(what) + ": '" + v.get<std::string>() + "' is not a number");
    return *n;
  }
  throw BadField(std::string(what) + ": expected a number or a hex string");
}
std::uint32_t num_or(const json& o, const char* key, std::uint32_t def) {
  auto it = o.find(key);
  return it == o.end() ? def : num(*it, key);
}
std::uint16_t u16_or(const json& o, const char* key, std::uint16_t def) {
  const auto v = num_or(o, key, def);
  if (v > 0xFFFF) throw BadField(std::string(key) + ": exceeds 16 bits");
  return static_cast<std::uint16_t>(v);
}
std::int64_t i64_or(const json& o, const char* key, std::int64_t def) {
  auto it = o.find(key);
  if (it == o.end()) return def;
  if (!it->is_number_integer()) throw BadField(std::string(key) + ": expected an integer");
  return it->get<std::int64_t>();
}
bool bool_or(const json& o, const char* key, bool def) {
  auto it = o.find(key);
  if (it == o.end()) return def;
  if (!it->is_boolean()) throw BadField(std::string(key) + ": expected true/false");
  return it->get<bool>();
}
Bytes bytes_of(const json& v, const char* what) {
  if (!v.is_string()) throw BadField(std::string(what) + ": expected a hex byte string");
  auto b = from_hex(v.get<std::string>());
  if (!b) throw BadField(std::string(what) + ": not a hex byte string");
  return *b;
}

const char* mode_name(codec::ChecksumMode m) {
  switch (m) {
    case codec::ChecksumMode::none:
      return "none";
    case codec::ChecksumMode::add:
      return "add";
    case codec::ChecksumMode::crc_ccitt:
      return "crc_ccitt";
    case codec::ChecksumMode::crc_kermit:
      return "crc_kermit";
  }
  return "none";
}
const char* coverage_name(codec::ChecksumCoverage c) {
  switch (c) {
    case codec::ChecksumCoverage::id_through_data:
      return "id_through_data";
    case codec::ChecksumCoverage::start_through_data:
      return "start_through_data";
    case codec::ChecksumCoverage::data_only:
      return "data_only";
  }
  return "id_through_data";
}
const char* policy_name(WritePolicy p) {
  switch (p) {
    case WritePolicy::reject:
      return "reject";
    case WritePolicy::clamp:
      return "clamp";
    case WritePolicy::accept:
      return "accept";
  }
  return "reject";
}

template <class E, std::size_t N>
E enum_of(const json& o, const char* key, E def, const std::pair<const char*, E> (&table)[N]) {
  auto it = o.find(key);
  if (it == o.end()) return def;
  if (!it->is_string()) throw BadField(std::string(key) + ": expected a string");
  const auto s = it->get<std::string>();
  for (const auto& [name, value] : table)
    if (s == name) return value;
  throw BadField(std::string(key) + ": unknown value '" + s + "'");
}

json curves_json(const std::map<std::uint16_t, Curve>& m) {
  json a = json::array();
  for (const auto& [id, c] : m)
    a.push_back({{"id", id}, {"info", to_hex(c.info)}, {"data", to_hex(c.data)}});
  return a;
}
std::map<std::uint16_t, Curve> curves_of(const json& a) {
  if (!a.is_array()) throw BadField("curves: expected an array");
  std::map<std::uint16_t, Curve> m;
  for (const auto& c : a)
    m[u16_or(c, "id", 0)] =
        Curve{bytes_of(c.at("info"), "curve info"), bytes_of(c.at("data"), "curve data")};
  return m;
}
json ct_json(const std::map<std::uint16_t, Bytes>& m) {
  json a = json::array();
  for (const auto& [e, b] : m) a.push_back({{"entry", e}, {"data", to_hex(b)}});
  return a;
}
std::map<std::uint16_t, Bytes> ct_of(const json& a) {
  if (!a.is_array()) throw BadField("command_table: expected an array");
  std::map<std::uint16_t, Bytes> m;
  for (const auto& c : a) {
    const auto e = u16_or(c, "entry", 0);
    if (e > 255) throw BadField("command_table: entry above 255");
    m[e] = bytes_of(c.at("data"), "command table data");
  }
  return m;
}

// The sections of a state file, one reader each (from_json); each throws
// BadField with the member's name.

// link, switches
void read_link(const json& j, DriveState& s) {
  if (auto it = j.find("link"); it != j.end()) {
    s.link.baud = num_or(*it, "baud", 57600);
    s.link.parity = enum_of(
        *it, "parity", transport::Parity::none,
        {std::pair{"none", transport::Parity::none}, std::pair{"even", transport::Parity::even},
         std::pair{"odd", transport::Parity::odd}});
    s.link.stop_bits = num_or(*it, "stop_bits", 1);
    if (auto v = transport::validate(s.link); !v.ok()) throw BadField("link: " + v.error().message);
  }
  if (auto it = j.find("switches"); it != j.end()) {
    HexSwitches sw{s.macid, s.link.baud};
    const auto id = num_or(*it, "macid", sw.macid);
    if (id > 0xFF) throw BadField("switches.macid: exceeds FFh");
    sw.macid = static_cast<std::uint8_t>(id);
    transport::SerialSettings probe = s.link;
    probe.baud = num_or(*it, "baud", sw.baud);
    if (auto v = transport::validate(probe); !v.ok())
      throw BadField("switches: " + v.error().message);
    sw.baud = probe.baud;
    s.switches = sw;
  }
}

// checksum
void read_checksum(const json& j, DriveState& s) {
  if (auto it = j.find("checksum"); it != j.end()) {
    s.checksum.mode = enum_of(
        *it, "mode", codec::ChecksumMode::none,
        {std::pair{"none", codec::ChecksumMode::none}, std::pair{"add", codec::ChecksumMode::add},
         std::pair{"crc_ccitt", codec::ChecksumMode::crc_ccitt},
         std::pair{"crc_kermit", codec::ChecksumMode::crc_kermit}});
    s.checksum.crc_init = u16_or(*it, "crc_init", 0xFFFF);
    s.checksum.coverage =
        enum_of(*it, "coverage", codec::ChecksumCoverage::id_through_data,
                {std::pair{"id_through_data", codec::ChecksumCoverage::id_through_data},
                 std::pair{"start_through_data", codec::ChecksumCoverage::start_through_data},
                 std::pair{"data_only", codec::ChecksumCoverage::data_only}});
  }
}

// default_response, mc_running, live, timing_us
void read_layout_and_timing(const json& j, DriveState& s) {
  if (auto it = j.find("default_response"); it != j.end()) {
    auto& L = s.layout;
    L.comm_state = bool_or(*it, "comm_state", L.comm_state);
    L.status_word = bool_or(*it, "status_word", L.status_word);
    L.state_var = bool_or(*it, "state_var", L.state_var);
    L.error_code = bool_or(*it, "error_code", L.error_code);
    L.warn_word = bool_or(*it, "warn_word", L.warn_word);
    L.echo_header = bool_or(*it, "echo_header", L.echo_header);
    L.monitoring_1 = bool_or(*it, "monitoring_1", L.monitoring_1);
    L.monitoring_2 = bool_or(*it, "monitoring_2", L.monitoring_2);
    L.mc_response = bool_or(*it, "mc_response", L.mc_response);
  }
  s.mc_running = bool_or(j, "mc_running", true);
  if (auto it = j.find("live"); it != j.end()) {
    auto& V = s.live;
    V.status_word = u16_or(*it, "status_word", V.status_word);
    V.state_var = u16_or(*it, "state_var", V.state_var);
    V.warn_word = u16_or(*it, "warn_word", V.warn_word);
    V.error_code = u16_or(*it, "error_code", V.error_code);
    V.monitoring_1 = num_or(*it, "monitoring_1", V.monitoring_1);
    V.monitoring_2 = num_or(*it, "monitoring_2", V.monitoring_2);
  }
  if (auto it = j.find("timing_us"); it != j.end()) {
    auto& T = s.timing;
    T.turnaround_us = i64_or(*it, "turnaround", T.turnaround_us);
    T.defaulting_us = i64_or(*it, "defaulting", T.defaulting_us);
    T.flash_save_us = i64_or(*it, "flash_save", T.flash_save_us);
    T.flash_save_max_us = i64_or(*it, "flash_save_max", T.flash_save_max_us);
    T.reset_us = i64_or(*it, "reset", T.reset_us);
    T.start_us = i64_or(*it, "start", T.start_us);
    T.rx_timeout_us = i64_or(*it, "rx_timeout", T.rx_timeout_us);
  }
}

// options
// options.checksum_param and its kin: {"upid": "20A0", "codes": {"0": "none", "2": "crc-ffff"}}
void read_comm_param(const json& options, const char* key, std::optional<Options::CommParam>& out,
                     std::initializer_list<const char*> names) {
  auto cp = options.find(key);
  if (cp == options.end()) return;
  const std::string where = std::string("options.") + key;
  if (!cp->is_object() || !cp->contains("upid") || !cp->contains("codes") ||
      !cp->at("codes").is_object())
    throw BadField(where + ": expected {\"upid\": \"20A0\", \"codes\": {\"0\": NAME}}");
  Options::CommParam p;
  p.upid = u16_or(*cp, "upid", 0);
  for (const auto& [code, name] : cp->at("codes").items()) {
    auto c = parse_number(code, true);
    if (!c) throw BadField(where + ".codes: key '" + code + "' is not a number");
    if (!name.is_string()) throw BadField(where + ".codes: expected a name for " + code);
    const std::string n = name.get<std::string>();
    bool known = false;
    std::string list;
    for (const char* k : names) {
      known = known || n == k;
      list += std::string(list.empty() ? "" : ", ") + k;
    }
    if (!known) throw BadField(where + ".codes: '" + n + "' is not one of " + list);
    p.codes[*c] = n;
  }
  out = std::move(p);
}

void read_options(const json& j, DriveState& s) {
  if (auto it = j.find("options"); it != j.end()) {
    auto& O = s.options;
    auto u8_or = [&](const char* k, std::uint8_t d) {
      const auto v = num_or(*it, k, d);
      if (v > 0xFF) throw BadField(std::string(k) + ": exceeds FFh");
      return static_cast<std::uint8_t>(v);
    };
    O.empty_list_state = u8_or("empty_list_state", O.empty_list_state);
    O.empty_list_upid = u16_or(*it, "empty_list_upid", O.empty_list_upid);
    O.missing_curve_zero_sizes =
        bool_or(*it, "missing_curve_zero_sizes", O.missing_curve_zero_sizes);
    O.write_policy =
        enum_of(*it, "write_policy", O.write_policy,
                {std::pair{"reject", WritePolicy::reject}, std::pair{"clamp", WritePolicy::clamp},
                 std::pair{"accept", WritePolicy::accept}});
    O.reject_state = u8_or("reject_state", O.reject_state);
    O.flash_refused_state = u8_or("flash_refused_state", O.flash_refused_state);
    O.missing_object_state = u8_or("missing_object_state", O.missing_object_state);
    O.respond_on_checksum_error =
        bool_or(*it, "respond_on_checksum_error", O.respond_on_checksum_error);
    O.respond_on_end_missing = bool_or(*it, "respond_on_end_missing", O.respond_on_end_missing);
    O.reload_tables_on_start = bool_or(*it, "reload_tables_on_start", O.reload_tables_on_start);
    O.ignore_while_busy = bool_or(*it, "ignore_while_busy", O.ignore_while_busy);
    O.missing_ct_entry_zero_size =
        bool_or(*it, "missing_ct_entry_zero_size", O.missing_ct_entry_zero_size);
    O.empty_list_echo_upid = bool_or(*it, "empty_list_echo_upid", O.empty_list_echo_upid);
    O.refusal_fields =
        enum_of(*it, "refusal_fields", O.refusal_fields,
                {std::pair{"echo", RefusalFields::echo}, std::pair{"zeros", RefusalFields::zeros},
                 std::pair{"arbitrary", RefusalFields::arbitrary}});
    O.refuse_config_while_mc_runs =
        bool_or(*it, "refuse_config_while_mc_runs", O.refuse_config_while_mc_runs);
    O.config_refused_state = u8_or("config_refused_state", O.config_refused_state);
    if (auto bc = it->find("baud_codes"); bc != it->end()) {
      if (!bc->is_object())
        throw BadField("options.baud_codes: expected an object of code -> baud rate");
      O.baud_codes.clear();
      for (const auto& [code, rate] : bc->items()) {
        auto c = parse_number(code, true);
        if (!c) throw BadField("options.baud_codes: key '" + code + "' is not a number");
        transport::SerialSettings probe;
        probe.baud = num(rate, "options.baud_codes value");
        if (auto v = transport::validate(probe); !v.ok())
          throw BadField("options.baud_codes: " + v.error().message);
        O.baud_codes[*c] = probe.baud;
      }
    }
    read_comm_param(*it, "checksum_param", O.checksum_param,
                    {"none", "add", "crc", "crc-ffff", "crc-0000", "crc-kermit"});
    read_comm_param(*it, "parity_param", O.parity_param, {"none", "even", "odd"});
    read_comm_param(*it, "stop_bits_param", O.stop_bits_param, {"1", "2"});
    O.silent_after_reset = bool_or(*it, "silent_after_reset", O.silent_after_reset);
    O.unanswered_saves = bool_or(*it, "unanswered_saves", O.unanswered_saves);
    O.stale_block_padding = bool_or(*it, "stale_block_padding", O.stale_block_padding);
    O.address_usage_request = bool_or(*it, "address_usage_request", O.address_usage_request);
    if (auto f = it->find("family"); f != it->end()) {
      const families::Family* fam =
          f->is_string() ? families::find(f->get<std::string>()) : nullptr;
      if (!fam) throw BadField("options.family: expected one of " + families::names());
      O.family = std::string(fam->name);
    }
  }
}

// parameters
void read_parameters(const json& j, DriveState& s) {
  if (auto it = j.find("parameters"); it != j.end()) {
    if (!it->is_array()) throw BadField("parameters: expected an array");
    for (const auto& q : *it) {
      Parameter p;
      if (!q.contains("upid")) throw BadField("parameters: entry without upid");
      p.upid = u16_or(q, "upid", 0);
      p.name = q.value("name", std::string());
      if (auto t = q.find("type"); t != q.end()) {
        if (t->is_string()) {
          auto code = type_from_name(t->get<std::string>());
          p.type = code ? type_code(*code) : static_cast<std::uint16_t>(num(*t, "type"));
        } else {
          p.type = static_cast<std::uint16_t>(num(*t, "type"));
        }
      }
      p.address_usage = u16_or(q, "address_usage", au::parameter);
      p.min = num_or(q, "min", 0);
      p.max = num_or(q, "max", 0xFFFFFFFF);
      p.def = num_or(q, "default", 0);
      p.rom = num_or(q, "rom", p.def);
      p.ram = num_or(q, "ram", p.rom);
      if (s.params.count(p.upid))
        throw BadField("parameters: UPID " + hex16(p.upid) + " given twice");
      s.params[p.upid] = std::move(p);
    }
  }
}

// curves, command_table, error_log, error_texts
void read_tables_and_log(const json& j, DriveState& s) {
  if (auto it = j.find("curves"); it != j.end()) {
    if (it->contains("flash")) s.curves_flash = curves_of(it->at("flash"));
    s.curves_ram = it->contains("ram") ? curves_of(it->at("ram")) : s.curves_flash;
  }
  if (auto it = j.find("command_table"); it != j.end()) {
    if (it->contains("flash")) s.ct_flash = ct_of(it->at("flash"));
    s.ct_ram = it->contains("ram") ? ct_of(it->at("ram")) : s.ct_flash;
  }
  if (auto it = j.find("error_log"); it != j.end()) {
    s.errors_occurred = u16_or(*it, "occurred", 0);
    if (auto e = it->find("entries"); e != it->end()) {
      for (const auto& x : *e)
        s.error_log.push_back({u16_or(x, "code", 0), num_or(x, "ms", 0), num_or(x, "hours", 0)});
    }
  }
  s.error_texts = default_error_texts();
  if (auto it = j.find("error_texts"); it != j.end()) {
    if (!it->is_object()) throw BadField("error_texts: expected an object of code -> text");
    for (const auto& [k, v] : it->items()) {
      auto code = parse_number(k, true);
      if (!code || *code > 0xFFFF || !v.is_string())
        throw BadField("error_texts: bad entry '" + k + "'");
      s.error_texts[static_cast<std::uint16_t>(*code)] = v.get<std::string>();
    }
  }
}

// "options" of the state file.
json options_json(const Options& O) {
  json j = {{"empty_list_state", hex8(O.empty_list_state)},
            {"empty_list_upid", hex16(O.empty_list_upid)},
            {"missing_curve_zero_sizes", O.missing_curve_zero_sizes},
            {"write_policy", policy_name(O.write_policy)},
            {"reject_state", hex8(O.reject_state)},
            {"flash_refused_state", hex8(O.flash_refused_state)},
            {"missing_object_state", hex8(O.missing_object_state)},
            {"respond_on_checksum_error", O.respond_on_checksum_error},
            {"respond_on_end_missing", O.respond_on_end_missing},
            {"reload_tables_on_start", O.reload_tables_on_start},
            {"ignore_while_busy", O.ignore_while_busy}};
  j["missing_ct_entry_zero_size"] = O.missing_ct_entry_zero_size;
  j["empty_list_echo_upid"] = O.empty_list_echo_upid;
  if (O.refusal_fields != RefusalFields::echo)
    j["refusal_fields"] = O.refusal_fields == RefusalFields::zeros ? "zeros" : "arbitrary";
  j["refuse_config_while_mc_runs"] = O.refuse_config_while_mc_runs;
  if (O.stale_block_padding) j["stale_block_padding"] = true;
  if (O.address_usage_request) j["address_usage_request"] = true;
  if (O.family != "E1100") j["family"] = O.family;
  j["config_refused_state"] = hex8(O.config_refused_state);
  if (O.baud_codes != Options::default_baud_codes()) {
    json codes = json::object();
    for (const auto& [code, rate] : O.baud_codes) codes[std::to_string(code)] = rate;
    j["baud_codes"] = std::move(codes);
  }
  auto comm_param = [&](const char* key, const std::optional<Options::CommParam>& p) {
    if (!p) return;
    json codes = json::object();
    for (const auto& [code, name] : p->codes) codes[std::to_string(code)] = name;
    j[key] = {{"upid", hex16(p->upid)}, {"codes", std::move(codes)}};
  };
  comm_param("checksum_param", O.checksum_param);
  comm_param("parity_param", O.parity_param);
  comm_param("stop_bits_param", O.stop_bits_param);
  if (O.silent_after_reset) j["silent_after_reset"] = true;
  if (O.unanswered_saves) j["unanswered_saves"] = true;
  return j;
}

// "parameters" of the state file.
json parameters_json(const std::map<std::uint16_t, Parameter>& ps) {
  json params = json::array();
  for (const auto& [upid, p] : ps) {
    json q = {{"upid", hex16(upid)}};
    if (!p.name.empty()) q["name"] = p.name;
    if (auto t = type_from_code(p.type))
      q["type"] = std::string(type_name(*t));
    else
      q["type"] = p.type;  // a code §10 does not list, kept as the number
    q["address_usage"] = hex16(p.address_usage);
    q["min"] = p.min;
    q["max"] = p.max;
    q["default"] = p.def;
    q["rom"] = p.rom;
    q["ram"] = p.ram;
    params.push_back(std::move(q));
  }
  return params;
}

}  // namespace

json to_json(const DriveState& s) {
  json j;
  j["format"] = kStateFormat;
  j["version"] = kStateVersion;
  j["macid"] = hex8(s.macid);
  j["link"] = {{"baud", s.link.baud},
               {"parity", std::string(transport::parity_name(s.link.parity))},
               {"stop_bits", s.link.stop_bits}};
  // Written only when they select something else than what is active now.
  if (s.switches && !(s.switches->macid == s.macid && s.switches->baud == s.link.baud))
    j["switches"] = {{"macid", hex8(s.switches->macid)}, {"baud", s.switches->baud}};
  j["checksum"] = {{"mode", mode_name(s.checksum.mode)},
                   {"crc_init", hex16(s.checksum.crc_init)},
                   {"coverage", coverage_name(s.checksum.coverage)}};
  const auto& L = s.layout;
  j["default_response"] = {{"comm_state", L.comm_state},     {"status_word", L.status_word},
                           {"state_var", L.state_var},       {"error_code", L.error_code},
                           {"warn_word", L.warn_word},       {"echo_header", L.echo_header},
                           {"monitoring_1", L.monitoring_1}, {"monitoring_2", L.monitoring_2},
                           {"mc_response", L.mc_response}};
  j["mc_running"] = s.mc_running;
  j["live"] = {{"status_word", hex16(s.live.status_word)}, {"state_var", hex16(s.live.state_var)},
               {"warn_word", hex16(s.live.warn_word)},     {"error_code", hex16(s.live.error_code)},
               {"monitoring_1", s.live.monitoring_1},      {"monitoring_2", s.live.monitoring_2}};
  const auto& T = s.timing;
  j["timing_us"] = {{"turnaround", T.turnaround_us}, {"defaulting", T.defaulting_us},
                    {"flash_save", T.flash_save_us}, {"flash_save_max", T.flash_save_max_us},
                    {"reset", T.reset_us},           {"start", T.start_us},
                    {"rx_timeout", T.rx_timeout_us}};
  j["options"] = options_json(s.options);
  j["parameters"] = parameters_json(s.params);
  j["curves"] = {{"flash", curves_json(s.curves_flash)}, {"ram", curves_json(s.curves_ram)}};
  j["command_table"] = {{"flash", ct_json(s.ct_flash)}, {"ram", ct_json(s.ct_ram)}};
  json log = json::array();
  for (const auto& e : s.error_log)
    log.push_back({{"code", hex16(e.code)}, {"ms", e.millis}, {"hours", e.hours}});
  j["error_log"] = {{"occurred", s.errors_occurred}, {"entries", std::move(log)}};
  json texts = json::object();
  for (const auto& [code, text] : s.error_texts) texts[hex16(code)] = text;
  j["error_texts"] = std::move(texts);
  return j;
}

Result<DriveState> from_json(const json& j) {
  try {
    if (!j.is_object()) throw BadField("top level: expected an object");
    if (j.value("format", std::string()) != kStateFormat)
      throw BadField(std::string("format: expected \"") + kStateFormat + "\"");
    const auto version = i64_or(j, "version", 0);
    if (version != kStateVersion)
      return Error(Errc::unsupported_version,
                   "sim state version " + std::to_string(version) + " (this build reads 1)");
    DriveState s;
    const auto macid = num_or(j, "macid", 0x11);
    if (macid > 0xFF) throw BadField("macid: exceeds FFh");
    s.macid = static_cast<std::uint8_t>(macid);
    read_link(j, s);
    read_checksum(j, s);
    read_layout_and_timing(j, s);
    read_options(j, s);
    read_parameters(j, s);
    read_tables_and_log(j, s);
    return s;
  } catch (const BadField& e) {
    return Error(Errc::parse_error, std::string("sim state: ") + e.what());
  } catch (const json::exception& e) {
    return Error(Errc::parse_error, std::string("sim state: ") + e.what());
  }
}

Result<DriveState> load_state(const std::string& path) {
  std::ifstream in(path);
  if (!in) return Error(Errc::file_error, "cannot open sim state file " + path);
  json j;
  try {
    in >> j;
  } catch (const json::exception& e) {
    return Error(Errc::parse_error, path + ": " + e.what());
  }
  auto r = from_json(j);
  if (!r.ok()) return Error(r.error().code, path + ": " + r.error().message);
  return r;
}

Result<void> save_state(const DriveState& s, const std::string& path) {
  const std::string tmp = path + ".tmp";
  {
    // Binary: the same bytes on Windows (no CR before each LF).
    std::ofstream out(tmp, std::ios::trunc | std::ios::binary);
    if (!out) return Error(Errc::file_error, "cannot write " + tmp);
    out << to_json(s).dump(2) << '\n';
    if (!out.flush()) return Error(Errc::file_error, "cannot write " + tmp);
  }
  // std::filesystem::rename, not std::rename: Windows' C library refuses to
  // rename over an existing file; libstdc++ replaces it there (MoveFileExW
  // with MOVEFILE_REPLACE_EXISTING), as rename(2) does on Linux.
  std::error_code ec;
  std::filesystem::rename(tmp, path, ec);
  if (ec) {
    std::filesystem::remove(tmp, ec);
    return Error(Errc::file_error, "cannot rename " + tmp + " to " + path);
  }
  return {};
}

Result<std::vector<DriveState>> load_line(const std::vector<std::string>& paths) {
  std::vector<DriveState> states;
  for (const auto& path : paths) {
    LMCFG_ASSIGN_OR_RETURN(auto state, load_state(path));
    for (std::size_t i = 0; i < states.size(); ++i) {
      if (states[i].macid == state.macid) {
        return Error(Errc::invalid_argument, path + ": MACID " + hex(state.macid, 2, "h") +
                                                 " is already used by " + paths[i] +
                                                 " on this line");
      }
    }
    states.push_back(std::move(state));
  }
  return states;
}

transport::LinkFactory state_file_link_factory() {
  return [](const transport::LinkRequest& req) -> Result<transport::OpenedLink> {
    std::vector<std::string> paths;
    for (std::size_t from = 0;;) {
      const auto comma = req.address.find(',', from);
      paths.push_back(req.address.substr(from, comma - from));
      if (comma == std::string::npos) break;
      from = comma + 1;
    }
    LMCFG_ASSIGN_OR_RETURN(auto states, load_line(paths));
    std::vector<std::shared_ptr<Drive>> drives;
    for (auto& state : states) drives.push_back(std::make_shared<Drive>(std::move(state)));
    // The line runs at the first drive's settings; a drive at other settings
    // hears nothing until the master switches to them.
    transport::SerialSettings line;
    line.baud = drives.front()->state().link.baud;
    line.parity = drives.front()->state().link.parity;
    line.stop_bits = drives.front()->state().link.stop_bits;
    auto bus = std::make_shared<Bus>(drives.front()->state().link);
    for (auto& d : drives) bus->add(d);
    auto link = std::make_unique<SimLink>(bus);
    link->set_real_time(req.real_time_peer);
    transport::OpenedLink out;
    out.line = line;
    out.link = std::move(link);
    out.on_close = [drives, paths]() -> Result<void> {
      for (std::size_t i = 0; i < drives.size(); ++i) {
        LMCFG_TRY(save_state(drives[i]->state(), paths[i]));
      }
      return {};
    };
    return out;
  };
}

}  // namespace lmcfg::sim
