#include "ops/drive_info.hpp"

#include <array>
#include <cstdio>
#include <nlohmann/json.hpp>

#include "db/database.hpp"

namespace lmcfg::ops {

std::string state_name(unsigned s) {
  // MC SW §3.1-3.20 (no state 7 is described)
  static const std::array<const char*, 21> kNames{"Not Ready To Switch On",
                                                  "Switch On Disabled",
                                                  "Ready To Switch On",
                                                  "Setup Error State",
                                                  "Error State",
                                                  "HW Test",
                                                  "Ready to Operate",
                                                  "",
                                                  "Operation Enabled",
                                                  "Homing",
                                                  "Clearance Check",
                                                  "Going To Initial Position",
                                                  "Aborting",
                                                  "Freezing",
                                                  "Error Behaviour Quick Stop",
                                                  "Going To Position",
                                                  "Jogging +",
                                                  "Jogging -",
                                                  "Linearizing",
                                                  "Phase Searching",
                                                  "Special Mode"};
  return s < kNames.size() ? kNames[s] : "";
}

namespace {
std::vector<std::string> bits(std::uint16_t w, const std::array<const char*, 16>& names) {
  std::vector<std::string> out;
  for (unsigned b = 0; b < 16; ++b) {
    if (w & (1u << b)) out.push_back(std::string(names[b]) + " (bit " + std::to_string(b) + ")");
  }
  return out;
}
}  // namespace

std::vector<std::string> status_word_bits(std::uint16_t w) {
  // MC SW §3.23
  static const std::array<const char*, 16> kNames{
      "Operation Enabled",    "Switch On Active",      "Enable Operation",   "Error",
      "Voltage Enable",       "/Quick Stop",           "Switch On Locked",   "Warning",
      "Event Handler Active", "Special Motion Active", "In Target Position", "Homed",
      "Fatal Error",          "Motion Active",         "Range Indicator 1",  "Range Indicator 2"};
  return bits(w, kNames);
}

std::vector<std::string> warn_word_bits(std::uint16_t w) {
  // MC SW §3.24
  static const std::array<const char*, 16> kNames{"Motor Hot Sensor",
                                                  "Motor Short Time Overload I^2t",
                                                  "Motor Supply Voltage Low",
                                                  "Motor Supply Voltage High",
                                                  "Position Lag Always",
                                                  "Position Lag Standing",
                                                  "Controller Hot",
                                                  "Motor Not Homed",
                                                  "PTC Sensor 1 Hot",
                                                  "Reserved PTC 2",
                                                  "RR Hot Calculated",
                                                  "Reserved",
                                                  "Reserved",
                                                  "Reserved",
                                                  "Interface Warn Flag",
                                                  "Application Warn Flag"};
  return bits(w, kNames);
}

Result<DriveInfo> read_drive_info(client::Client& c, const db::Database& db, std::size_t max_log) {
  DriveInfo i;
  LMCFG_ASSIGN_OR_RETURN(i.response, c.default_response(codec::ResponseRequest::warn_word));
  LMCFG_ASSIGN_OR_RETURN(i.actual_error, c.actual_error_text());
  LMCFG_ASSIGN_OR_RETURN(i.counters, c.error_counters());
  for (std::uint16_t n = 0; n < i.counters.logged && n < max_log; ++n) {
    LMCFG_ASSIGN_OR_RETURN(auto e, c.error_log_entry(n));
    ErrorLogLine l{e.code, e.millis, e.hours, {}};
    if (const auto* d = db.error("mc", e.code)) {
      l.text = d->text;
    } else {
      LMCFG_ASSIGN_OR_RETURN(l.text, c.error_text(e.code));
    }
    i.log.push_back(std::move(l));
  }
  return i;
}

std::string render_info(const DriveInfo& i) {
  std::string out;
  char buf[200];
  const auto& r = i.response;
  if (r.state_var) {
    const unsigned main = *r.state_var >> 8;
    const std::string name = state_name(main);
    std::snprintf(buf, sizeof buf, "state:        %u%s%s (state var %04Xh)\n", main,
                  name.empty() ? "" : " ", name.c_str(), *r.state_var);
    out += buf;
  }
  if (r.status_word) {
    std::snprintf(buf, sizeof buf, "status word:  %04Xh\n", *r.status_word);
    out += buf;
    for (const auto& b : status_word_bits(*r.status_word)) out += "              " + b + "\n";
  }
  if (r.value) {  // requested with the warn word (§6.1.3)
    const auto warn = static_cast<std::uint16_t>(*r.value & 0xFFFF);
    std::snprintf(buf, sizeof buf, "warn word:    %04Xh\n", warn);
    out += buf;
    for (const auto& b : warn_word_bits(warn)) out += "              " + b + "\n";
  }
  out +=
      "actual error: " + (i.actual_error.empty() ? std::string("(none)") : i.actual_error) + "\n";
  std::snprintf(buf, sizeof buf, "error log:    %u logged, %u occurred in total\n",
                i.counters.logged, i.counters.occurred);
  out += buf;
  for (std::size_t n = 0; n < i.log.size(); ++n) {
    const auto& l = i.log[n];
    std::snprintf(buf, sizeof buf, "  #%zu %04Xh %s at %u h %u.%03u s\n", n, l.code, l.text.c_str(),
                  l.hours, l.millis / 1000, l.millis % 1000);
    out += buf;
  }
  return out;
}

bool ErrorState::in_error() const {
  if (state_var && (*state_var >> 8) == 4) return true;
  return status_word && (*status_word & ((1u << 3) | (1u << 12)));
}

Result<ErrorState> read_error_state(client::Client& c) {
  ErrorState s;
  LMCFG_ASSIGN_OR_RETURN(auto r, c.default_response());
  s.state_var = r.state_var;
  s.status_word = r.status_word;
  LMCFG_ASSIGN_OR_RETURN(s.actual_error, c.actual_error_text());
  return s;
}

std::string render_error_state(const ErrorState& s) {
  char buf[160];
  std::string out = "drive state:";
  if (s.state_var) {
    const unsigned main = *s.state_var >> 8;
    const std::string name = state_name(main);
    std::snprintf(buf, sizeof buf, " %u%s%s (state var %04Xh)", main, name.empty() ? "" : " ",
                  name.c_str(), *s.state_var);
    out += buf;
  }
  if (s.status_word) {
    std::snprintf(buf, sizeof buf, "%s status word %04Xh", s.state_var ? "," : "", *s.status_word);
    out += buf;
    std::string flags;
    if (*s.status_word & (1u << 3)) flags += "Error";
    if (*s.status_word & (1u << 12))
      flags += std::string(flags.empty() ? "" : ", ") + "Fatal Error";
    if (!flags.empty()) out += " (" + flags + ")";
  }
  if (!s.state_var && !s.status_word) out += " unknown";
  out += "; actual error: " + (s.actual_error.empty() ? std::string("none") : s.actual_error);
  return out;
}

std::string render_info_json(const DriveInfo& i) {
  nlohmann::ordered_json j;
  char hex[8];
  auto h4 = [&](unsigned v) {
    std::snprintf(hex, sizeof hex, "%04X", v & 0xFFFFu);
    return std::string(hex);
  };
  const auto& r = i.response;
  if (r.state_var) {
    const unsigned main = *r.state_var >> 8;
    j["state"] = {{"main", main},
                  {"name", state_name(main)},
                  {"state_var", *r.state_var},
                  {"state_var_hex", h4(*r.state_var)}};
  } else {
    j["state"] = nullptr;
  }
  auto word = [&](std::optional<std::uint16_t> w, std::vector<std::string> (*bits)(std::uint16_t)) {
    if (!w) return nlohmann::ordered_json(nullptr);
    return nlohmann::ordered_json{{"value", *w}, {"hex", h4(*w)}, {"bits", bits(*w)}};
  };
  j["status_word"] = word(r.status_word, &status_word_bits);
  std::optional<std::uint16_t> warn;
  if (r.value) warn = static_cast<std::uint16_t>(*r.value & 0xFFFF);
  j["warn_word"] = word(warn, &warn_word_bits);
  j["actual_error"] = i.actual_error;
  j["error_log"] = {{"logged", i.counters.logged}, {"occurred", i.counters.occurred}};
  auto entries = nlohmann::ordered_json::array();
  for (const auto& l : i.log) {
    entries.push_back({{"code", l.code},
                       {"code_hex", h4(l.code)},
                       {"text", l.text},
                       {"hours", l.hours},
                       {"millis", l.millis}});
  }
  j["error_log"]["entries"] = std::move(entries);
  return j.dump() + "\n";
}

}  // namespace lmcfg::ops
