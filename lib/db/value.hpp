#pragma once
// Parameter values: type codes (LinRS §10), decoding the 4-byte value field
// (LinRS §9: a bit in the lowest bit, a byte in the lowest byte, a word in
// the two lower bytes), display formatting with scale/unit/enum labels, parsing
// user input back to the raw field, and range checks. Pure: no I/O, no database.
#include <cstdint>
#include <optional>
#include <string>
#include <string_view>
#include <vector>

#include "common/result.hpp"
#include "common/types.hpp"

namespace lmcfg::db {

// The type codes of LinRS §10 live in common/types.hpp; the database's
// users name them db::TypeCode as well.
using lmcfg::field_integer;
using lmcfg::IntRange;
using lmcfg::is_signed_type;
using lmcfg::is_text_type;
using lmcfg::type_from_code;
using lmcfg::type_from_name;
using lmcfg::type_name;
using lmcfg::type_range;
using lmcfg::type_size;
using lmcfg::TypeCode;

// One UPID syntax for every command and file-free input: 1..4 hex digits,
// optionally with a "0x" prefix or an "h" suffix, any case: "13A2", "13a2h",
// "0x13A2". Errc::invalid_argument naming the text otherwise.
Result<std::uint16_t> parse_upid(std::string_view text);

// A decoded 4-byte field.
struct Value {
  enum class Kind { Integer, Text, Raw } kind = Kind::Raw;
  std::int64_t integer = 0;  // Kind::Integer (sign-extended for SINT types)
  std::string text;          // Kind::Text: up to 4 characters, stops at NUL
  std::uint32_t raw = 0;     // always: the field as it travelled
};
// BOOL/RADIO_DIR_BIT: lowest bit; 8/16-bit types: lowest byte/word, sign-extended
// for SINT8/SINT16; 32-bit: whole field (SINT32 sign-extended); text types: the
// four bytes as characters, lowest byte first; LIN_FLOAT: Kind::Raw.
Value decode_value(TypeCode t, std::uint32_t raw) noexcept;
// Inverse for integers: the value masked to the type's width (upper bytes 0).
std::uint32_t encode_integer(TypeCode t, std::int64_t v) noexcept;
// Up to 4 characters, first character in the lowest byte, NUL-padded.
std::uint32_t encode_text(std::string_view s) noexcept;

struct EnumLabel {
  std::int64_t raw;
  std::string label;
};

// Everything needed to show and parse one value (a parameter's or a motion
// command parameter's). Empty optional = unknown in the database.
struct ValueSpec {
  std::optional<TypeCode> type;
  std::optional<double> scale;  // raw -> unit multiplier
  std::string unit;
  std::vector<EnumLabel> labels;
  std::optional<std::int64_t> min;  // raw
  std::optional<std::int64_t> max;  // raw
};

// Decimal text of raw*scale with as many decimals as the scale has (trailing
// zeros dropped): 1000000 x 0.0001 -> "100", 500000 x 1e-6 -> "0.5".
std::string format_scaled(std::int64_t raw, double scale);
// "16", "100 mm", "By Parameter (2)", "\"Unna\"", "0x12345678" (unknown type).
std::string format_value(const ValueSpec& spec, std::uint32_t raw);

// Parses user input into the raw 4-byte field and range-checks it:
//  - an enum label (case-insensitive), or "Label (n)";
//  - a number followed by the unit ("100 mm", "0.5m/s"): scaled, divided by
//    the scale, must land on a whole raw step;
//  - a bare number: RAW ("1000000", "-5", "0x0F4240", "F4240h");
//  - text types: up to 4 characters, optionally in double quotes.
// Errors: Errc::invalid_argument (unreadable) or Errc::validation_failed (range).
Result<std::uint32_t> parse_value(const ValueSpec& spec, std::string_view text);

// Type range first, then the spec's min/max (raw). Messages name the limit and
// show it scaled when the spec has a scale.
Result<void> check_range(const ValueSpec& spec, std::int64_t raw_value);

}  // namespace lmcfg::db
