#include "common/text.hpp"

#include "common/bytes.hpp"

namespace lmcfg {

namespace {

// The length of the well-formed UTF-8 sequence at s[i], 0 when it is not one
// (RFC 3629 §4, the table of well-formed byte sequences).
std::size_t sequence_at(std::string_view s, std::size_t i) noexcept {
  auto at = [&](std::size_t k) { return static_cast<unsigned char>(s[k]); };
  const unsigned char b = at(i);
  if (b < 0x80) return 1;
  std::size_t n = 0;
  unsigned char lo = 0x80, hi = 0xBF;  // the allowed range of the second byte
  if (b >= 0xC2 && b <= 0xDF) {
    n = 2;
  } else if (b >= 0xE0 && b <= 0xEF) {
    n = 3;
    if (b == 0xE0) lo = 0xA0;  // no overlong forms
    if (b == 0xED) hi = 0x9F;  // no surrogates
  } else if (b >= 0xF0 && b <= 0xF4) {
    n = 4;
    if (b == 0xF0) lo = 0x90;  // no overlong forms
    if (b == 0xF4) hi = 0x8F;  // nothing above U+10FFFF
  } else {
    return 0;
  }
  if (i + n > s.size()) return 0;
  if (at(i + 1) < lo || at(i + 1) > hi) return 0;
  for (std::size_t k = 2; k < n; ++k)
    if (at(i + k) < 0x80 || at(i + k) > 0xBF) return 0;
  return n;
}

bool is_control(std::string_view s, std::size_t i) noexcept {
  const auto b = static_cast<unsigned char>(s[i]);
  if (b < 0x20 || b == 0x7F) return true;
  // U+0080..U+009F are C2 80..C2 9F.
  return b == 0xC2 && i + 1 < s.size() && static_cast<unsigned char>(s[i + 1]) <= 0x9F;
}

}  // namespace

std::size_t invalid_utf8_at(std::string_view s) noexcept {
  for (std::size_t i = 0; i < s.size();) {
    const std::size_t n = sequence_at(s, i);
    if (n == 0) return i;
    i += n;
  }
  return std::string_view::npos;
}

std::size_t control_at(std::string_view s) noexcept {
  for (std::size_t i = 0; i < s.size();) {
    if (is_control(s, i)) return i;
    const std::size_t n = sequence_at(s, i);
    i += n == 0 ? 1 : n;
  }
  return std::string_view::npos;
}

std::string escape_invalid_utf8(std::string_view s) {
  std::string out;
  out.reserve(s.size());
  for (std::size_t i = 0; i < s.size();) {
    const std::size_t n = sequence_at(s, i);
    if (n == 0) {
      out += "\\x" + hex(static_cast<unsigned char>(s[i]), 2);
      ++i;
      continue;
    }
    out.append(s.substr(i, n));
    i += n;
  }
  return out;
}

std::string one_line(std::string_view s) {
  const std::string valid = escape_invalid_utf8(s);
  std::string out;
  out.reserve(valid.size());
  for (std::size_t i = 0; i < valid.size();) {
    if (is_control(valid, i)) {
      out += ' ';
      i += static_cast<unsigned char>(valid[i]) == 0xC2 ? 2 : 1;
      continue;
    }
    out += valid[i++];
  }
  return out;
}

std::string log_text(std::string_view s) {
  std::string out;
  out.reserve(s.size());
  for (std::size_t i = 0; i < s.size();) {
    const std::size_t n = sequence_at(s, i);
    if (n == 0 || is_control(s, i)) {
      for (std::size_t k = 0; k < (n == 0 ? 1 : n); ++k)
        out += "\\x" + hex(static_cast<unsigned char>(s[i + k]), 2);
      i += n == 0 ? 1 : n;
      continue;
    }
    out.append(s.substr(i, n));
    i += n;
  }
  return out;
}

Result<void> check_line(std::string_view field, std::string_view value, std::size_t max_bytes) {
  const std::string name(field);
  if (const auto bad = invalid_utf8_at(value); bad != std::string_view::npos) {
    return Error(Errc::invalid_argument, name + " is not valid UTF-8 (byte 0x" +
                                             hex(static_cast<unsigned char>(value[bad]), 2) +
                                             " at offset " + std::to_string(bad) +
                                             "): send UTF-8 text");
  }
  if (const auto c = control_at(value); c != std::string_view::npos) {
    const auto b = static_cast<unsigned char>(value[c]);
    const unsigned code = b == 0xC2 ? static_cast<unsigned char>(value[c + 1]) : b;
    return Error(Errc::invalid_argument, name + " contains a control character (0x" + hex(code, 2) +
                                             " at offset " + std::to_string(c) +
                                             "): give one line without control characters");
  }
  if (value.size() > max_bytes) {
    return Error(Errc::invalid_argument, name + " is " + std::to_string(value.size()) +
                                             " bytes long, at most " + std::to_string(max_bytes) +
                                             " are accepted: shorten it");
  }
  return {};
}

}  // namespace lmcfg
