#include "can/frame.hpp"

#include <algorithm>
#include <cstdio>

namespace lmcfg::can {

Frame Frame::standard(std::uint32_t id, ByteView payload) {
  Frame f;
  f.id = id;
  f.len = static_cast<std::uint8_t>(std::min<std::size_t>(payload.size(), 8));
  std::copy_n(payload.begin(), f.len, f.data.begin());
  return f;
}

std::string describe(const Frame& f) {
  char head[32];
  std::snprintf(head, sizeof head, f.extended ? "%08X%s [%u]" : "%03X%s [%u]", f.id,
                f.extended ? "x" : "", static_cast<unsigned>(f.len));
  std::string s = head;
  if (f.rtr) return s + " RTR";
  for (std::size_t i = 0; i < f.len && i < 8; ++i) s += " " + hex(f.data[i], 2);
  return s;
}

Result<void> validate(const Frame& f) {
  const std::uint32_t max = f.extended ? 0x1FFFFFFF : 0x7FF;
  if (f.id > max) {
    return Error(Errc::invalid_argument, "CAN identifier " + hex(f.id, f.extended ? 8 : 3, "h") +
                                             " does not fit " + (f.extended ? "29" : "11") +
                                             " bits");
  }
  if (f.len > 8) {
    return Error(Errc::invalid_argument,
                 "CAN frame length " + std::to_string(f.len) + " is more than 8 bytes");
  }
  return {};
}

namespace slcan {
namespace {

std::optional<std::uint32_t> hex_field(std::string_view s) {
  std::uint32_t v = 0;
  for (char c : s) {
    const int d = hex_digit_value(c);
    if (d < 0) return std::nullopt;
    v = v * 16 + static_cast<std::uint32_t>(d);
  }
  return v;
}

constexpr std::size_t kLongestLine = 1 + 8 + 1 + 16 + 4;  // T, ID, L, data, timestamp

}  // namespace

namespace {
constexpr unsigned kRates[] = {10000,  20000,  50000,  100000, 125000,
                               250000, 500000, 800000, 1000000};
}

std::optional<unsigned> bitrate_of(char digit) {
  if (digit < '0' || digit > '8') return std::nullopt;
  return kRates[digit - '0'];
}

Result<std::string> bitrate_command(unsigned bitrate) {
  for (unsigned i = 0; i < std::size(kRates); ++i) {
    if (kRates[i] == bitrate) return "S" + std::to_string(i) + "\r";
  }
  return Error(Errc::invalid_argument,
               "CAN bit rate " + std::to_string(bitrate) +
                   " is not one slcan can set (DeviceNet: 125000, 250000 or 500000)");
}

std::string encode(const Frame& f) {
  std::string s(1, f.extended ? (f.rtr ? 'R' : 'T') : (f.rtr ? 'r' : 't'));
  s += hex(f.id, f.extended ? 8 : 3);
  s += static_cast<char>('0' + std::min<int>(f.len, 8));
  if (!f.rtr) {
    for (std::size_t i = 0; i < f.len && i < 8; ++i) s += hex(f.data[i], 2);
  }
  return s + "\r";
}

std::optional<Frame> parse_frame_line(std::string_view line) {
  if (line.empty()) return std::nullopt;
  Frame f;
  const char kind = line[0];
  if (kind != 't' && kind != 'T' && kind != 'r' && kind != 'R') return std::nullopt;
  f.extended = kind == 'T' || kind == 'R';
  f.rtr = kind == 'r' || kind == 'R';
  const std::size_t id_len = f.extended ? 8 : 3;
  if (line.size() < 1 + id_len + 1) return std::nullopt;
  auto id = hex_field(line.substr(1, id_len));
  const int len = hex_digit_value(line[1 + id_len]);
  if (!id || len < 0 || len > 8) return std::nullopt;
  f.id = *id;
  f.len = static_cast<std::uint8_t>(len);
  std::size_t at = 2 + id_len;
  if (!f.rtr) {
    if (line.size() < at + 2 * f.len) return std::nullopt;
    for (std::size_t i = 0; i < f.len; ++i, at += 2) {
      auto b = hex_field(line.substr(at, 2));
      if (!b) return std::nullopt;
      f.data[i] = static_cast<std::uint8_t>(*b);
    }
  }
  // An adapter with time stamps on appends 4 hex digits; anything else is wrong.
  const auto rest = line.substr(at);
  if (!rest.empty() && (rest.size() != 4 || !hex_field(rest))) return std::nullopt;
  if (!validate(f).ok()) return std::nullopt;
  return f;
}

std::vector<Event> Decoder::feed(ByteView bytes) {
  std::vector<Event> out;
  for (std::uint8_t b : bytes) {
    if (b == 0x07) {
      line_.clear();
      out.push_back(Bell{});
    } else if (b == '\r' || b == '\n') {
      if (b == '\n' && line_.empty()) continue;  // CR LF from some adapters
      if (line_.empty()) {
        out.push_back(Ack{});
      } else if ((line_ == "z" || line_ == "Z")) {
        out.push_back(Ack{line_[0]});
      } else if (auto f = parse_frame_line(line_)) {
        out.push_back(*f);
      } else {
        out.push_back(Unknown{line_});
      }
      line_.clear();
    } else if (line_.size() < kLongestLine) {
      line_.push_back(static_cast<char>(b));
    } else {
      out.push_back(Unknown{line_});
      line_.clear();
    }
  }
  return out;
}

}  // namespace slcan
}  // namespace lmcfg::can
