#include "devicenet/command.hpp"

namespace lmcfg::devicenet {
namespace {

// Words low byte first (common/bytes.hpp), read in order.
std::uint16_t word_at(ByteView b, std::size_t& at) {
  const auto w = get_u16le(b, at);
  at += 2;
  return w;
}

// A poll command or response whose size does not match the configured modules.
Result<void> check_size(const char* what, std::size_t got, std::size_t want) {
  if (got == want) return {};
  return Error(got < want ? Errc::frame_short : Errc::frame_overlong,
               std::string(what) + " of " + std::to_string(got) +
                   " byte(s); the configured modules make " + std::to_string(want));
}

std::size_t master_count(const IoLayout& l) {
  std::size_t n = 0;
  for (bool m : l.masters) n += m;
  return n;
}

}  // namespace

char motor_letter(Motor m) { return static_cast<char>('A' + static_cast<int>(m)); }

std::uint16_t CommandWord::encode() const {
  std::uint16_t w = static_cast<std::uint16_t>(id & 0x7F);
  if (toggle) w |= 0x0080;
  for (Motor m : kMotors)
    if (motors[static_cast<int>(m)])
      w |= static_cast<std::uint16_t>(0x1000u << static_cast<int>(m));
  return w;
}

CommandWord CommandWord::decode(std::uint16_t w) {
  CommandWord c;
  c.id = static_cast<std::uint8_t>(w & 0x7F);
  c.toggle = (w & 0x0080) != 0;
  for (Motor m : kMotors)
    c.motors[static_cast<int>(m)] = (w & (0x1000u << static_cast<int>(m))) != 0;
  return c;
}

std::vector<std::string> Status::names() const {
  static constexpr const char* kLow[8] = {"INIT Done",     "RUN State",      "ERROR State",
                                          "INIT State",    "DISABLE State",  "Emergency Stop",
                                          "ERROR Pending", "WARNING Pending"};
  std::vector<std::string> out;
  for (int b = 0; b < 8; ++b)
    if (low & (1u << b)) out.push_back(kLow[b]);
  for (Motor m : kMotors) {
    const std::string motor = std::string("Motor ") + motor_letter(m);
    if (curve_done_toggle(m)) out.push_back("Curve Done " + std::string(1, motor_letter(m)));
    if (in_position(m)) out.push_back("In Position " + motor);
  }
  for (Motor m : kMotors) {
    const std::string motor = std::string("Motor ") + motor_letter(m);
    if (following_error(m)) out.push_back(motor + " Following Error");
    if (position_range(m)) out.push_back(motor + " Position Range");
    if (over_temperature(m)) out.push_back(motor + " Over temperature");
    if (command_toggle(m)) out.push_back(motor + " Command Toggle");
  }
  return out;
}

bool toggle_to_send(const Status& s, Motor m) { return !s.command_toggle(m); }
bool command_done(const Status& s, Motor m, bool sent_toggle) {
  return s.command_toggle(m) == sent_toggle;
}

bool toggle_command(std::uint8_t id) {
  switch (id & 0x7F) {
    case 0x13:
    case 0x15:
    case 0x19:
    case 0x20:
    case 0x22:
      return true;
  }
  return false;
}

std::size_t IoLayout::command_size() const {
  return 2 * ((control_in ? 1 : 0) + (addressed_in ? 2 : 0) +
              (direct_in ? 2 * master_count(*this) : 0));
}

std::size_t IoLayout::response_size() const {
  return 2 * ((status_out ? 2 : 0) + (addressed_out ? 2 : 0) +
              ((direct_out1 ? 1 : 0) + (direct_out2 ? 1 : 0)) * master_count(*this));
}

Bytes encode_command(const IoLayout& l, const PollCommand& c) {
  Bytes out;
  if (l.control_in) put_u16le(out, c.control);
  if (l.addressed_in) {
    put_u16le(out, c.addressed.encode());
    put_u16le(out, c.addressed_value);
  }
  if (l.direct_in) {
    for (Motor m : kMotors) {
      const auto i = static_cast<std::size_t>(m);
      if (!l.masters[i]) continue;
      put_u16le(out, c.direct[i].encode());
      put_u16le(out, c.direct_value[i]);
    }
  }
  return out;
}

Result<PollResponse> decode_response(const IoLayout& l, ByteView bytes) {
  LMCFG_TRY(check_size("poll response", bytes.size(), l.response_size()));
  PollResponse r;
  std::size_t at = 0;
  if (l.status_out) {
    r.status.low = word_at(bytes, at);
    r.status.high = word_at(bytes, at);
  }
  if (l.addressed_out) {
    r.addressed_echo = CommandWord::decode(word_at(bytes, at));
    r.addressed_value = word_at(bytes, at);
  }
  for (Motor m : kMotors) {
    const auto i = static_cast<std::size_t>(m);
    if (!l.masters[i]) continue;
    if (l.direct_out1) r.direct_out1[i] = word_at(bytes, at);
    if (l.direct_out2) r.direct_out2[i] = word_at(bytes, at);
  }
  return r;
}

Result<PollCommand> decode_command(const IoLayout& l, ByteView bytes) {
  LMCFG_TRY(check_size("poll command", bytes.size(), l.command_size()));
  PollCommand c;
  std::size_t at = 0;
  if (l.control_in) c.control = word_at(bytes, at);
  if (l.addressed_in) {
    c.addressed = CommandWord::decode(word_at(bytes, at));
    c.addressed_value = word_at(bytes, at);
  }
  if (l.direct_in) {
    for (Motor m : kMotors) {
      const auto i = static_cast<std::size_t>(m);
      if (!l.masters[i]) continue;
      c.direct[i] = CommandWord::decode(word_at(bytes, at));
      c.direct_value[i] = word_at(bytes, at);
    }
  }
  return c;
}

Bytes encode_response(const IoLayout& l, const PollResponse& r) {
  Bytes out;
  if (l.status_out) {
    put_u16le(out, r.status.low);
    put_u16le(out, r.status.high);
  }
  if (l.addressed_out) {
    put_u16le(out, r.addressed_echo.encode());
    put_u16le(out, r.addressed_value);
  }
  for (Motor m : kMotors) {
    const auto i = static_cast<std::size_t>(m);
    if (!l.masters[i]) continue;
    if (l.direct_out1) put_u16le(out, r.direct_out1[i]);
    if (l.direct_out2) put_u16le(out, r.direct_out2[i]);
  }
  return out;
}

std::string_view coded_error_text(std::uint16_t code) {
  // §5.2 "Response: Get Coded Error": the application errors.
  switch (code) {
    case 0x8100:
      return "Application needs DN servo controller";
    case 0x8101:
      return "DeviceNet MACID already in use";
    case 0x8104:
      return "Processor speed not supported";
    case 0x8108:
      return "Unknown command";
    case 0x8110:
      return "Drive not specified";
    case 0x8111:
      return "Drive not master";
    case 0x8112:
      return "Drive not in serial mode";
    case 0x8118:
      return "Range error";
    case 0x8120:
      return "Encoder not exists";
    case 0x8121:
      return "Encoder in SSI mode";
    case 0x8130:
      return "Curve doesn't exists";
    case 0x8131:
      return "Curve type mismatch";
    case 0x8132:
      return "Curve processing";
    case 0x8140:
      return "CAN no error";
    case 0x8141:
      return "CAN stuff error";
    case 0x8142:
      return "CAN form error";
    case 0x8143:
      return "CAN acknowledge error";
    case 0x8144:
      return "CAN bit 1 error";
    case 0x8145:
      return "CAN CRC error";
    case 0x8148:
      return "CAN BOFF error";
  }
  return {};
}

}  // namespace lmcfg::devicenet
