#pragma once
// Little-endian byte helpers (LinRS §4: lowest byte first) and hex text.
#include <cstdint>
#include <optional>
#include <span>
#include <string>
#include <string_view>
#include <vector>

namespace lmcfg {

using Bytes = std::vector<std::uint8_t>;
using ByteView = std::span<const std::uint8_t>;

// The characters of `s` as bytes (ASCII protocols such as slcan).
inline ByteView as_bytes(std::string_view s) {
  return ByteView(reinterpret_cast<const std::uint8_t*>(s.data()), s.size());
}

inline std::uint16_t get_u16le(ByteView b, std::size_t off) {
  return static_cast<std::uint16_t>(b[off] | (b[off + 1] << 8));
}
inline std::uint32_t get_u32le(ByteView b, std::size_t off) {
  return static_cast<std::uint32_t>(b[off]) | (static_cast<std::uint32_t>(b[off + 1]) << 8) |
         (static_cast<std::uint32_t>(b[off + 2]) << 16) |
         (static_cast<std::uint32_t>(b[off + 3]) << 24);
}
inline void put_u16le(Bytes& out, std::uint16_t v) {
  out.push_back(static_cast<std::uint8_t>(v & 0xFF));
  out.push_back(static_cast<std::uint8_t>(v >> 8));
}
inline void put_u32le(Bytes& out, std::uint32_t v) {
  for (int i = 0; i < 4; ++i) out.push_back(static_cast<std::uint8_t>((v >> (8 * i)) & 0xFF));
}

// "01 11 05" (upper case, space separated).
std::string to_hex(ByteView b, char sep = ' ');
// `v` in upper-case hex with at least `digits` digits (as printf's %0*X), then
// `suffix`: hex(0x13A2, 4) == "13A2", hex(0x11, 2, "h") == "11h" (the manuals'
// notation). The one hex formatter of lmcfg.
std::string hex(std::uint32_t v, int digits, std::string_view suffix = {});
// The value of one hex digit (either case), -1 for any other character.
int hex_digit_value(char c) noexcept;
// Accepts hex digits with optional spaces/colons between byte pairs; nullopt on odd count or
// non-hex.
std::optional<Bytes> from_hex(std::string_view text);
// ASCII case-insensitive equality ("uint16" == "UINT16").
bool iequals(std::string_view a, std::string_view b) noexcept;
// Parses "0x13A2", "13A2h", "13A2" as hex when hex_default, or decimal otherwise ("5026").
std::optional<std::uint32_t> parse_number(std::string_view text, bool hex_default);

}  // namespace lmcfg
