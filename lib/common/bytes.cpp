#include "common/bytes.hpp"

#include <cctype>

namespace lmcfg {

std::string to_hex(ByteView b, char sep) {
  static constexpr char kDigits[] = "0123456789ABCDEF";
  std::string s;
  s.reserve(b.size() * 3);
  for (std::size_t i = 0; i < b.size(); ++i) {
    if (i != 0 && sep != '\0') s.push_back(sep);
    s.push_back(kDigits[b[i] >> 4]);
    s.push_back(kDigits[b[i] & 0xF]);
  }
  return s;
}

std::string hex(std::uint32_t v, int digits, std::string_view suffix) {
  static constexpr char kDigits[] = "0123456789ABCDEF";
  std::string s;
  do {
    s.insert(s.begin(), kDigits[v & 0xF]);
    v >>= 4;
  } while (v != 0);
  if (static_cast<int>(s.size()) < digits)
    s.insert(0, static_cast<std::size_t>(digits) - s.size(), '0');
  s += suffix;
  return s;
}

bool iequals(std::string_view a, std::string_view b) noexcept {
  if (a.size() != b.size()) return false;
  for (std::size_t i = 0; i < a.size(); ++i)
    if (std::tolower(static_cast<unsigned char>(a[i])) !=
        std::tolower(static_cast<unsigned char>(b[i])))
      return false;
  return true;
}

int hex_digit_value(char c) noexcept {
  if (c >= '0' && c <= '9') return c - '0';
  if (c >= 'a' && c <= 'f') return c - 'a' + 10;
  if (c >= 'A' && c <= 'F') return c - 'A' + 10;
  return -1;
}

std::optional<Bytes> from_hex(std::string_view text) {
  Bytes out;
  int pending = -1;
  for (char c : text) {
    if (c == ' ' || c == ':' || c == '\n' || c == '\t' || c == '\r') {
      if (pending >= 0) return std::nullopt;  // a lone nibble before a separator
      continue;
    }
    int v = hex_digit_value(c);
    if (v < 0) return std::nullopt;
    if (pending < 0) {
      pending = v;
    } else {
      out.push_back(static_cast<std::uint8_t>(pending << 4 | v));
      pending = -1;
    }
  }
  if (pending >= 0) return std::nullopt;
  return out;
}

std::optional<std::uint32_t> parse_number(std::string_view t, bool hex_default) {
  bool hex = hex_default;
  if (t.size() > 2 && t[0] == '0' && (t[1] == 'x' || t[1] == 'X')) {
    t.remove_prefix(2);
    hex = true;
  } else if (!t.empty() && (t.back() == 'h' || t.back() == 'H')) {
    t.remove_suffix(1);
    hex = true;
  }
  if (t.empty() || t.size() > (hex ? 8u : 10u)) return std::nullopt;
  std::uint64_t v = 0;
  for (char c : t) {
    int d = hex ? hex_digit_value(c) : (std::isdigit(static_cast<unsigned char>(c)) ? c - '0' : -1);
    if (d < 0) return std::nullopt;
    v = v * (hex ? 16u : 10u) + static_cast<unsigned>(d);
  }
  if (v > 0xFFFFFFFFull) return std::nullopt;
  return static_cast<std::uint32_t>(v);
}

}  // namespace lmcfg
