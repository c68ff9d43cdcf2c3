#include "devicenet/catalogue.hpp"

#include <algorithm>
#include <array>

#include "devicenet/messages.hpp"

namespace lmcfg::devicenet {
namespace {

// DeviceNet §5.2: each detail section says whether the command addresses "one
// drive" (a motor bit) or "the LinMot servo controller". The live ones are the
// state words, positions and IO the texts describe as actual values.
constexpr ValueCommand kCommands[] = {
    // get   settable per_motor live  module
    {0x02, false, false, true, false},  // Status Low Word
    {0x03, false, false, true, false},  // Status High Word
    {0x04, true, false, true, false},   // Control Word
    {0x06, false, false, true, false},  // System Warn State
    {0x06, false, true, true, false},   // Motor Warn State
    {0x08, false, false, true, false},  // System Error State
    {0x08, false, true, true, false},   // Motor Error State
    {0x0A, false, false, true, false},  // Coded Error
    {0x0C, true, false, true, false},   // Controller IO
    {0x10, true, true, true, false},    // Position Setpoint
    {0x18, true, true, true, false},    // Actual Position
    {0x24, true, true, false, false},   // (Rise) Curve Number
    {0x26, true, true, false, false},   // Fall Curve Number
    {0x28, true, true, false, false},   // Curve Offset
    {0x2A, true, true, false, false},   // Curve Amplitude
    {0x2C, true, true, false, false},   // Curve Speed
    {0x30, true, true, false, false},   // Controller Maximal Current
    {0x32, true, true, false, false},   // Controller Current Offset
    {0x34, true, true, false, false},   // Controller P
    {0x36, true, true, false, false},   // Controller D
    {0x38, true, true, false, false},   // Controller I
    {0x3A, true, true, false, false},   // Controller FF Friction
    {0x3C, true, true, false, false},   // Controller FF Acceleration
    {0x3E, true, true, false, false},   // Controller FF Deceleration
    {0x40, true, true, false, false},   // Minimal Position
    {0x42, true, true, false, false},   // Maximal Position
    {0x44, true, true, false, false},   // Position Range Low Limit
    {0x46, true, true, false, false},   // Position Range High Limit
    {0x48, true, true, false, false},   // In Position Low Limit
    {0x4A, true, true, false, false},   // In Position High Limit
    {0x4C, true, true, false, false},   // Following Error Low Limit
    {0x4E, true, true, false, false},   // Following Error High Limit
    {0x50, true, true, false, false},   // Filter Maximal Speed
    {0x52, true, true, false, false},   // Filter Maximal Acceleration
    {0x56, true, true, false, false},   // Analog 0V Position
    {0x58, true, true, false, false},   // Analog 10V Position
    {0x5A, true, true, false, false},   // Two Point 0 Position
    {0x5C, true, true, false, false},   // Two Point 1 Position
    {0x60, true, false, true, true},    // Encoder 1 Position
    {0x62, true, true, false, true},    // CAM Length
    {0x64, true, false, true, true},    // Extended IO
    {0x66, true, false, false, true},   // Encoder 1 Offset
    {0x6A, true, true, false, true},    // CAM Delay
    {0x70, true, true, false, false},   // Direct Out 1 Variable
    {0x72, true, true, false, false},   // Direct Out 2 Variable
    {0x74, true, true, false, false},   // Direct Out 1 Address
    {0x76, true, true, false, false},   // Direct Out 2 Address
};

struct ModuleName {
  std::string_view name;
  bool IoLayout::*flag;
};
constexpr ModuleName kModules[] = {
    {"control-in", &IoLayout::control_in},       {"addressed-in", &IoLayout::addressed_in},
    {"direct-in", &IoLayout::direct_in},         {"status-out", &IoLayout::status_out},
    {"addressed-out", &IoLayout::addressed_out}, {"direct-out-1", &IoLayout::direct_out1},
    {"direct-out-2", &IoLayout::direct_out2},
};

}  // namespace

std::span<const ValueCommand> value_commands() { return kCommands; }

const ValueCommand* value_command(std::uint8_t get) {
  for (const auto& c : kCommands)
    if (c.get == get) return &c;
  return nullptr;
}

std::vector<std::string> module_names(const IoLayout& l) {
  std::vector<std::string> out;
  for (const auto& m : kModules)
    if (l.*m.flag) out.emplace_back(m.name);
  if (l.direct_in || l.direct_out1 || l.direct_out2)
    for (Motor m : kMotors)
      if (l.masters[static_cast<std::size_t>(m)])
        out.push_back(std::string("master:") + motor_letter(m));
  return out;
}

Result<IoLayout> parse_modules(const std::vector<std::string>& names) {
  IoLayout l;
  for (const auto& m : kModules) l.*m.flag = false;
  l.masters = {};
  bool any_master = false;
  for (const auto& n : names) {
    if (n.size() == 8 && n.rfind("master:", 0) == 0 && n[7] >= 'A' && n[7] <= 'D') {
      l.masters[static_cast<std::size_t>(n[7] - 'A')] = true;
      any_master = true;
      continue;
    }
    const auto* m = std::find_if(std::begin(kModules), std::end(kModules),
                                 [&](const ModuleName& k) { return k.name == n; });
    if (m == std::end(kModules)) {
      return Error(Errc::invalid_argument,
                   "unknown IO module '" + n +
                       "' (expected control-in, addressed-in, direct-in, status-out, "
                       "addressed-out, direct-out-1, direct-out-2, master:A..master:D)");
    }
    l.*m->flag = true;
  }
  if (!any_master) l.masters = {true, false, false, false};
  return l;
}

Result<IoLayout> parse_modules(std::string_view comma_separated) {
  std::vector<std::string> names;
  std::size_t at = 0;
  while (at <= comma_separated.size()) {
    const auto comma = std::min(comma_separated.find(',', at), comma_separated.size());
    names.emplace_back(comma_separated.substr(at, comma - at));
    at = comma + 1;
  }
  return parse_modules(names);
}

namespace {

std::string command_text(const CommandWord& w) {
  std::string motors;
  for (Motor m : kMotors)
    if (w.motors[static_cast<std::size_t>(m)]) motors += motor_letter(m);
  return "command " + hex(w.id, 2, "h") + (motors.empty() ? "" : " motor " + motors) + " toggle " +
         (w.toggle ? "1" : "0");
}

std::string poll_text(const can::Frame& f, const IoLayout& l, bool response) {
  const ByteView body = f.payload();
  if (response ? body.size() != l.response_size() : body.size() != l.command_size())
    return " (fragment or another layout)";
  if (response) {
    auto r = decode_response(l, body);
    if (!r.ok()) return {};
    return ": status " + hex(r->status.low, 4, "h") + " " + hex(r->status.high, 4, "h") +
           ", echo " + command_text(r->addressed_echo) + " value " +
           hex(r->addressed_value, 4, "h");
  }
  auto c = decode_command(l, body);
  if (!c.ok()) return {};
  return ": " + command_text(c->addressed) + " value " + hex(c->addressed_value, 4, "h");
}

}  // namespace

std::string describe_frame(const can::Frame& f, const IoLayout& layout) {
  std::string text = describe_identifier(f.id);
  if (f.extended || f.rtr || f.id >= 0x600) return text;
  if (f.id >= 0x400) {
    const auto message = static_cast<Group2>(f.id & 7);
    if (message == Group2::master_io_poll) return text + poll_text(f, layout, false);
    if (message == Group2::duplicate_mac_check) return text;
    auto e = Explicit::decode(f.payload());
    if (!e.ok()) return text;
    std::string s = text + ": " + std::string(service_name(e->service)) +
                    (e->response ? " response" : " request");
    for (auto b : e->data) s += " " + hex(b, 2);
    return s;
  }
  if (((f.id >> 6) & 0xF) == kSlavePollResponse) return text + poll_text(f, layout, true);
  return text;
}

Result<std::uint8_t> parse_mac_id(std::string_view option, std::string_view text) {
  const auto mac = parse_number(text, false);
  if (!mac || *mac > 63) {
    return Error(Errc::invalid_argument, std::string(option) + " '" + std::string(text) +
                                             "' is not a DeviceNet MAC ID 0..63");
  }
  return static_cast<std::uint8_t>(*mac);
}

Result<std::array<bool, 4>> parse_motor_list(std::string_view option, std::string_view text) {
  std::array<bool, 4> motors{};
  for (char c : text) {
    if (c == ',') continue;
    const int m = c - 'A';
    if (m < 0 || m > 3 || motors[static_cast<std::size_t>(m)]) {
      return Error(Errc::invalid_argument, std::string(option) + " '" + std::string(text) +
                                               "': expected motors A..D, each once, e.g. A,B");
    }
    motors[static_cast<std::size_t>(m)] = true;
  }
  return motors;
}

std::string target_name(std::optional<Motor> m) {
  return m ? std::string("motor ") + motor_letter(*m) : std::string("the controller");
}

}  // namespace lmcfg::devicenet
