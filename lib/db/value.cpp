#include "db/value.hpp"

#include <algorithm>
#include <array>
#include <cctype>
#include <cmath>
#include <cstdio>
#include <cstdlib>

#include "common/bytes.hpp"

namespace lmcfg::db {

namespace {

std::string_view trim(std::string_view s) {
  while (!s.empty() && std::isspace(static_cast<unsigned char>(s.front()))) s.remove_prefix(1);
  while (!s.empty() && std::isspace(static_cast<unsigned char>(s.back()))) s.remove_suffix(1);
  return s;
}

// Unit comparison: case-sensitive, ignoring spaces and '^' ("m/s^2" == "m/s2").
std::string unit_key(std::string_view u) {
  std::string k;
  for (char c : u)
    if (c != ' ' && c != '^') k.push_back(c);
  return k;
}

// Decimals needed to show multiples of `scale` exactly (0.0001 -> 4), capped at 12.
int scale_decimals(double scale) {
  double s = std::fabs(scale);
  for (int d = 0; d < 12; ++d) {
    double m = s * std::pow(10.0, d);
    if (std::fabs(m - std::round(m)) < 1e-9 * std::max(1.0, m)) return d;
  }
  return 12;
}

std::string range_text(const ValueSpec& spec, std::int64_t raw) {
  std::string s = std::to_string(raw);
  if (spec.scale) {
    s += " (" + format_scaled(raw, *spec.scale);
    if (!spec.unit.empty()) s += " " + spec.unit;
    s += ")";
  }
  return s;
}

std::optional<std::int64_t> parse_raw_integer(std::string_view t) {
  bool neg = false;
  if (!t.empty() && (t[0] == '-' || t[0] == '+')) {
    neg = t[0] == '-';
    t.remove_prefix(1);
  }
  if (t.empty()) return std::nullopt;
  bool hex = (t.size() > 2 && t[0] == '0' && (t[1] == 'x' || t[1] == 'X')) || t.back() == 'h' ||
             t.back() == 'H';
  if (hex && neg) return std::nullopt;
  auto v = parse_number(t, false);
  if (!v) return std::nullopt;
  return neg ? -static_cast<std::int64_t>(*v) : static_cast<std::int64_t>(*v);
}

}  // namespace

Value decode_value(TypeCode t, std::uint32_t raw) noexcept {
  Value v;
  v.raw = raw;
  if (t == TypeCode::LinFloat) return v;
  if (is_text_type(t)) {
    v.kind = Value::Kind::Text;
    for (int i = 0; i < 4; ++i) {
      char c = static_cast<char>((raw >> (8 * i)) & 0xFF);
      if (c == '\0') break;
      v.text.push_back(c);
    }
    return v;
  }
  v.kind = Value::Kind::Integer;
  switch (t) {
    case TypeCode::Bool:
    case TypeCode::RadioDirBit:
      v.integer = raw & 1u;
      break;
    case TypeCode::UInt8:
    case TypeCode::EnumDir8:
      v.integer = raw & 0xFFu;
      break;
    case TypeCode::SInt8:
      v.integer = static_cast<std::int8_t>(raw & 0xFFu);
      break;
    case TypeCode::UInt16:
    case TypeCode::RadioDir16:
    case TypeCode::EnumDir16:
      v.integer = raw & 0xFFFFu;
      break;
    case TypeCode::SInt16:
      v.integer = static_cast<std::int16_t>(raw & 0xFFFFu);
      break;
    case TypeCode::SInt32:
      v.integer = static_cast<std::int32_t>(raw);
      break;
    default:  // UInt32
      v.integer = raw;
      break;
  }
  return v;
}

std::uint32_t encode_integer(TypeCode t, std::int64_t v) noexcept {
  auto u = static_cast<std::uint32_t>(static_cast<std::uint64_t>(v) & 0xFFFFFFFFull);
  switch (type_size(t)) {
    case 1:
      return (t == TypeCode::Bool || t == TypeCode::RadioDirBit) ? (u & 1u) : (u & 0xFFu);
    case 2:
      return u & 0xFFFFu;
    default:
      return u;
  }
}

std::uint32_t encode_text(std::string_view s) noexcept {
  std::uint32_t r = 0;
  for (std::size_t i = 0; i < s.size() && i < 4; ++i)
    r |= static_cast<std::uint32_t>(static_cast<unsigned char>(s[i])) << (8 * i);
  return r;
}

std::string format_scaled(std::int64_t raw, double scale) {
  int d = scale_decimals(scale);
  double v = static_cast<double>(raw) * scale;
  char buf[64];
  std::snprintf(buf, sizeof buf, "%.*f", d, v);
  std::string s = buf;
  if (s.find('.') != std::string::npos) {
    while (s.back() == '0') s.pop_back();
    if (s.back() == '.') s.pop_back();
  }
  if (s == "-0") s = "0";
  return s;
}

std::string format_value(const ValueSpec& spec, std::uint32_t raw) {
  char buf[16];
  if (!spec.type || *spec.type == TypeCode::LinFloat) {
    // A label the seed states for this exact field value needs no type.
    for (const auto& l : spec.labels)
      if (l.raw == static_cast<std::int64_t>(raw))
        return l.label + " (" + std::to_string(raw) + ")";
    std::snprintf(buf, sizeof buf, "0x%08X", raw);
    return buf;
  }
  Value v = decode_value(*spec.type, raw);
  if (v.kind == Value::Kind::Text) return "\"" + v.text + "\"";
  for (const auto& l : spec.labels)
    if (l.raw == v.integer) return l.label + " (" + std::to_string(v.integer) + ")";
  std::string s = spec.scale ? format_scaled(v.integer, *spec.scale) : std::to_string(v.integer);
  if (!spec.unit.empty()) s += " " + spec.unit;
  return s;
}

Result<void> check_range(const ValueSpec& spec, std::int64_t raw_value) {
  if (spec.type) {
    if (auto r = type_range(*spec.type)) {
      if (raw_value < r->min || raw_value > r->max)
        return Error(Errc::validation_failed,
                     "value " + std::to_string(raw_value) + " is outside the " +
                         std::string(type_name(*spec.type)) + " range " + std::to_string(r->min) +
                         ".." + std::to_string(r->max));
    }
  }
  if (spec.min && raw_value < *spec.min)
    return Error(Errc::validation_failed, "value " + range_text(spec, raw_value) +
                                              " is below the minimum " +
                                              range_text(spec, *spec.min));
  if (spec.max && raw_value > *spec.max)
    return Error(Errc::validation_failed, "value " + range_text(spec, raw_value) +
                                              " is above the maximum " +
                                              range_text(spec, *spec.max));
  return {};
}

Result<std::uint32_t> parse_value(const ValueSpec& spec, std::string_view input) {
  std::string_view t = trim(input);
  if (t.empty())
    return Error(Errc::invalid_argument,
                 "empty value: expected a number, a value with unit or a label");

  if (spec.type && is_text_type(*spec.type)) {
    std::string_view s = t;
    if (s.size() >= 2 && s.front() == '"' && s.back() == '"') {
      s = s.substr(1, s.size() - 2);
    } else if (s.size() > 2 && s[0] == '0' && (s[1] == 'x' || s[1] == 'X')) {
      if (auto n = parse_number(s, true)) return *n;
    }
    if (s.size() > 4)
      return Error(Errc::validation_failed, "text \"" + std::string(s) +
                                                "\" is longer than the 4 characters of a " +
                                                std::string(type_name(*spec.type)) + " value");
    return encode_text(s);
  }

  // Enum label, or "Label (n)".
  for (const auto& l : spec.labels) {
    if (iequals(t, l.label) || iequals(t, l.label + " (" + std::to_string(l.raw) + ")")) {
      LMCFG_TRY(check_range(spec, l.raw));
      return spec.type ? encode_integer(*spec.type, l.raw) : static_cast<std::uint32_t>(l.raw);
    }
  }

  std::int64_t raw = 0;
  if (auto whole = parse_raw_integer(t)) {
    raw = *whole;  // bare number: raw ("1000000", "-5", "0x0F4240", "F4240h")
  } else {
    // A number followed by its unit.
    std::size_t i = 0;
    if (i < t.size() && (t[i] == '-' || t[i] == '+')) ++i;
    while (i < t.size() && (std::isdigit(static_cast<unsigned char>(t[i])) || t[i] == '.')) ++i;
    std::string numstr(t.substr(0, i));
    std::string_view unit = trim(t.substr(i));
    char* end = nullptr;
    double x = numstr.empty() ? 0.0 : std::strtod(numstr.c_str(), &end);
    if (numstr.empty() || end != numstr.c_str() + numstr.size()) {
      std::string msg =
          "cannot read \"" + std::string(t) + "\": expected a raw number, a value with unit";
      if (!spec.labels.empty()) {
        msg += " or one of the labels";
        for (std::size_t k = 0; k < spec.labels.size(); ++k)
          msg += (k ? ", \"" : " \"") + spec.labels[k].label + "\"";
      }
      return Error(Errc::invalid_argument, msg);
    }
    if (unit.empty())
      return Error(
          Errc::invalid_argument,
          "\"" + std::string(t) + "\" has decimals but no unit: a bare number is a raw value" +
              (spec.unit.empty() ? std::string()
                                 : "; write it as \"" + std::string(t) + " " + spec.unit + "\""));
    if (spec.unit.empty() || unit_key(unit) != unit_key(spec.unit))
      return Error(Errc::invalid_argument,
                   "unit \"" + std::string(unit) + "\" in \"" + std::string(t) +
                       "\" does not match " +
                       (spec.unit.empty() ? std::string("this value, which has no unit")
                                          : "the value's unit \"" + spec.unit + "\""));
    double scale = spec.scale.value_or(1.0);
    double steps = x / scale;
    double rounded = std::round(steps);
    if (std::fabs(steps - rounded) > std::max(1e-6, 1e-12 * std::fabs(steps)))
      return Error(Errc::validation_failed, "\"" + std::string(t) +
                                                "\" is not a multiple of the resolution " +
                                                format_scaled(1, scale) + " " + spec.unit);
    if (std::fabs(rounded) > 9.0e15)
      return Error(Errc::validation_failed, "\"" + std::string(t) + "\" is far out of range");
    raw = static_cast<std::int64_t>(rounded);
  }
  LMCFG_TRY(check_range(spec, raw));
  if (!spec.type) {
    if (raw < -2147483648ll || raw > 0xFFFFFFFFll)
      return Error(Errc::validation_failed,
                   "value " + std::to_string(raw) + " does not fit the 4-byte value field");
    return static_cast<std::uint32_t>(static_cast<std::uint64_t>(raw) & 0xFFFFFFFFull);
  }
  return encode_integer(*spec.type, raw);
}

Result<std::uint16_t> parse_upid(std::string_view text) {
  std::string_view t = text;
  if (t.size() > 2 && t[0] == '0' && (t[1] == 'x' || t[1] == 'X')) {
    t.remove_prefix(2);
  } else if (!t.empty() && (t.back() == 'h' || t.back() == 'H')) {
    t.remove_suffix(1);
  }
  std::uint32_t v = 0;
  bool ok = !t.empty() && t.size() <= 4;
  for (char c : t) {
    int d = -1;
    if (c >= '0' && c <= '9') d = c - '0';
    if (c >= 'a' && c <= 'f') d = c - 'a' + 10;
    if (c >= 'A' && c <= 'F') d = c - 'A' + 10;
    if (d < 0) ok = false;
    v = v * 16 + static_cast<std::uint32_t>(d < 0 ? 0 : d);
  }
  if (!ok)
    return Error(Errc::invalid_argument, "\"" + std::string(text) +
                                             "\" is not a UPID (expected up to 4 hex digits: "
                                             "13A2, 13a2h or 0x13A2)");
  return static_cast<std::uint16_t>(v);
}

}  // namespace lmcfg::db
