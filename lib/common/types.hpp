#pragma once
// Parameter type codes of LinRS §10 ("Supported Parameter Types"), the one
// table of lmcfg: the database, the configuration files' readers, the restore
// plan and the simulated drive all use it. Pure.
#include <cstdint>
#include <optional>
#include <string_view>

namespace lmcfg {

// Values are the wire type codes (§10 05h 04h answers, UPID list entries).
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

// The wire code as the 16-bit field of §10 carries it.
constexpr std::uint16_t type_code(TypeCode t) noexcept { return static_cast<std::uint16_t>(t); }
// "BOOL", "UINT8", ... exactly as LinRS §10 / upid-db/FORMAT.md spell them.
std::string_view type_name(TypeCode t) noexcept;
// Case-insensitive; also accepts the seed 001 spelling "SInt32", "UInt16".
std::optional<TypeCode> type_from_name(std::string_view name) noexcept;
// 00h..0Fh; nullopt for a code §10 does not list (a drive may still send one).
std::optional<TypeCode> type_from_code(unsigned code) noexcept;
// Bytes the value occupies in the 4-byte field (BOOL/RADIO_DIR_BIT: 1; the
// string types and LIN_FLOAT: 4). Also the size of a motion command parameter.
unsigned type_size(TypeCode t) noexcept;
// Four characters per value: STRING, CAP_DIR, STRINGLET, CAP_DIRLET.
bool is_text_type(TypeCode t) noexcept;
bool is_signed_type(TypeCode t) noexcept;

struct IntRange {
  std::int64_t min;
  std::int64_t max;
};
// Integer range of the type; nullopt for LIN_FLOAT and the text types.
std::optional<IntRange> type_range(TypeCode t) noexcept;

// The 4-byte field as an integer of its type, or nullopt when it does not fit:
// the upper bytes must be zero, or the sign extension for signed types (a
// drive may send either for SINT8/SINT16); BOOL/RADIO_DIR_BIT only 0 or 1.
// Text types and LIN_FLOAT: the field as is. Never truncates.
std::optional<std::int64_t> field_integer(TypeCode t, std::uint32_t raw) noexcept;

}  // namespace lmcfg
