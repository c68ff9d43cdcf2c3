#include "config/io_common.hpp"

#include "config/model.hpp"

namespace lmcfg::config::detail {

std::string upid_hex(std::uint32_t upid) {
  static constexpr char kDigits[] = "0123456789ABCDEF";
  std::string s(4, '0');
  for (std::size_t i = 4; i-- > 0;) {
    s[i] = kDigits[upid & 0xF];
    upid >>= 4;
  }
  return s;
}

std::optional<std::uint16_t> parse_upid_hex(std::string_view s) noexcept {
  if (s.size() != 4) return std::nullopt;
  unsigned v = 0;
  for (char c : s) {
    int d = hex_digit_value(c);
    if (d < 0) return std::nullopt;
    v = v << 4 | static_cast<unsigned>(d);
  }
  return static_cast<std::uint16_t>(v);
}

std::string devicenet_motor_text(int motor) {
  if (motor == kDevicenetController) return "controller";
  return std::string(1, static_cast<char>('A' + motor));
}

std::optional<int> parse_motor_letter(std::string_view s) noexcept {
  if (s.size() != 1 || s[0] < 'A' || s[0] > 'D') return std::nullopt;
  return s[0] - 'A';
}

std::optional<int> parse_devicenet_motor(std::string_view s) noexcept {
  if (s == "controller") return kDevicenetController;
  return parse_motor_letter(s);
}

std::string command_hex(std::uint8_t id) { return upid_hex(id).substr(2); }

std::optional<std::uint8_t> parse_command_hex(std::string_view s) noexcept {
  if (s.size() != 2) return std::nullopt;
  const int hi = hex_digit_value(s[0]), lo = hex_digit_value(s[1]);
  if (hi < 0 || lo < 0) return std::nullopt;
  return static_cast<std::uint8_t>(hi << 4 | lo);
}

std::vector<std::string> block_rows(ByteView b) {
  std::vector<std::string> rows;
  rows.reserve((b.size() + kBytesPerRow - 1) / kBytesPerRow);
  for (std::size_t off = 0; off < b.size(); off += kBytesPerRow)
    rows.push_back(to_hex(b.subspan(off, std::min(kBytesPerRow, b.size() - off))));
  return rows;
}

std::optional<Bytes> parse_row(std::string_view s) {
  // "HH( HH){0,15}"
  if (s.size() < 2 || s.size() > kBytesPerRow * 3 - 1 || (s.size() + 1) % 3 != 0)
    return std::nullopt;
  Bytes out;
  out.reserve((s.size() + 1) / 3);
  for (std::size_t i = 0; i < s.size(); i += 3) {
    int hi = hex_digit_value(s[i]);
    int lo = hex_digit_value(s[i + 1]);
    if (hi < 0 || lo < 0) return std::nullopt;
    if (i + 2 < s.size() && s[i + 2] != ' ') return std::nullopt;
    out.push_back(static_cast<std::uint8_t>(hi << 4 | lo));
  }
  return out;
}

std::optional<std::uint64_t> parse_decimal(std::string_view s) noexcept {
  if (s.empty() || s.size() > 19) return std::nullopt;
  if (s.size() > 1 && s[0] == '0') return std::nullopt;
  std::uint64_t v = 0;
  for (char c : s) {
    if (c < '0' || c > '9') return std::nullopt;
    v = v * 10 + static_cast<unsigned>(c - '0');
  }
  return v;
}

std::optional<std::int64_t> parse_signed_decimal(std::string_view s) noexcept {
  bool neg = false;
  if (!s.empty() && s[0] == '-') {
    neg = true;
    s.remove_prefix(1);
  }
  auto v = parse_decimal(s);
  if (!v || *v > 0x7FFFFFFFFFFFFFFFull) return std::nullopt;
  const auto sv = static_cast<std::int64_t>(*v);
  if (neg && sv == 0) return std::nullopt;
  return neg ? -sv : sv;
}

Result<void> check_format_id(std::string_view format, const std::string& where) {
  if (format != kFormatId)
    return Error(Errc::unsupported_version, where + ": expected format \"" +
                                                std::string(kFormatId) + "\", found \"" +
                                                std::string(format) + "\"");
  return {};
}

Result<void> check_format_version(std::int64_t version, std::string_view name,
                                  const std::string& where) {
  if (version > kFormatVersion)
    return Error(Errc::unsupported_version, std::string(name) + ": file format_version " +
                                                std::to_string(version) +
                                                " is newer than this lmcfg supports (" +
                                                std::to_string(kFormatVersion) + "); update lmcfg");
  if (version < kOldestFormatVersion)
    return Error(Errc::unsupported_version,
                 where + ": expected format_version " + std::to_string(kOldestFormatVersion) +
                     ".." + std::to_string(kFormatVersion) + ", found " + std::to_string(version));
  return {};
}

}  // namespace lmcfg::config::detail
