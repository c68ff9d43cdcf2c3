#pragma once
// Parameter values: type codes (seed 003 §10), decoding the 4-byte value field
// (seed 003 §9: a bit in the lowest bit, a byte in the lowest byte, a word in
// the two lower bytes), display formatting with scale/unit/enum labels, parsing
// user input back to the raw field, and range checks. Pure: no I/O, no database.
#include <cstdint>
#include <optional>
#include <string>
#include <string_view>
#include <vector>

#include "common/result.hpp"

namespace lmcfg::db {

// Seed 003 §10 "Supported Parameter Types". Values are the wire type codes.
enum class TypeCode : std::uint8_t {
  Bool = 0x00,
  UInt8 = 0x01,
  SInt8 = 0x02,
  UInt16 = 0x03,
  SInt16 = 0x04,
  UInt32 = 0x05,
  SInt32 = 0x06,
  LinFloat = 0x07,  // "not used as parameter"
  String = 0x08,
  CapDir = 0x09,
  RadioDirBit = 0x0A,
  RadioDir16 = 0x0B,
  EnumDir8 = 0x0C,
  EnumDir16 = 0x0D,
  Stringlet = 0x0E,  // 4 characters of a string
  CapDirlet = 0x0F,  // 4 characters of a string
};

// "BOOL", "UINT8", ... exactly as seed 003 §10 / upid-db/FORMAT.md spell them.
std::string_view type_name(TypeCode t) noexcept;
// Case-insensitive; also accepts the seed 001 spelling "SInt32", "UInt16".
std::optional<TypeCode> type_from_name(std::string_view name) noexcept;
std::optional<TypeCode> type_from_code(unsigned code) noexcept;
// Bytes the value occupies in the 4-byte field (BOOL/RADIO_DIR_BIT: 1; the
// string types and LIN_FLOAT: 4). Also the size of a motion command parameter.
unsigned type_size(TypeCode t) noexcept;
// Four characters per value: STRING, CAP_DIR, STRINGLET, CAP_DIRLET.
bool is_text_type(TypeCode t) noexcept;
bool is_signed_type(TypeCode t) noexcept;

// One UPID syntax for every command and file-free input: 1..4 hex digits,
// optionally with a "0x" prefix or an "h" suffix, any case: "13A2", "13a2h",
// "0x13A2". Errc::invalid_argument naming the text otherwise.
Result<std::uint16_t> parse_upid(std::string_view text);

struct IntRange {
  std::int64_t min;
  std::int64_t max;
};
// Integer range of the type; nullopt for LIN_FLOAT and the text types.
std::optional<IntRange> type_range(TypeCode t) noexcept;

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
// The 4-byte field as an integer of its type, or nullopt when it does not fit:
// the upper bytes must be zero, or the sign extension for signed types (a
// drive may send either for SINT8/SINT16); BOOL/RADIO_DIR_BIT only 0 or 1.
// Text types and LIN_FLOAT: the field as is. Never truncates.
std::optional<std::int64_t> field_integer(TypeCode t, std::uint32_t raw) noexcept;
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
