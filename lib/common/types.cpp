#include "common/types.hpp"

#include <array>

#include "common/bytes.hpp"

namespace lmcfg {

namespace {

constexpr std::array<std::string_view, 16> kTypeNames = {
    "BOOL",      "UINT8",      "SINT8",     "UINT16",    "SINT16",        "UINT32",
    "SINT32",    "LIN_FLOAT",  "STRING",    "CAP_DIR",   "RADIO_DIR_BIT", "RADIO_DIR16",
    "ENUM_DIR8", "ENUM_DIR16", "STRINGLET", "CAP_DIRLET"};

}  // namespace

std::string_view type_name(TypeCode t) noexcept {
  return kTypeNames[static_cast<unsigned>(t) & 0x0F];
}

std::optional<TypeCode> type_from_name(std::string_view name) noexcept {
  for (unsigned i = 0; i < kTypeNames.size(); ++i)
    if (iequals(name, kTypeNames[i])) return static_cast<TypeCode>(i);
  return std::nullopt;
}

std::optional<TypeCode> type_from_code(unsigned code) noexcept {
  if (code > 0x0F) return std::nullopt;
  return static_cast<TypeCode>(code);
}

unsigned type_size(TypeCode t) noexcept {
  switch (t) {
    case TypeCode::Bool:
    case TypeCode::RadioDirBit:
    case TypeCode::UInt8:
    case TypeCode::SInt8:
    case TypeCode::EnumDir8:
      return 1;
    case TypeCode::UInt16:
    case TypeCode::SInt16:
    case TypeCode::RadioDir16:
    case TypeCode::EnumDir16:
      return 2;
    default:
      return 4;
  }
}

bool is_text_type(TypeCode t) noexcept {
  return t == TypeCode::String || t == TypeCode::CapDir || t == TypeCode::Stringlet ||
         t == TypeCode::CapDirlet;
}

bool is_signed_type(TypeCode t) noexcept {
  return t == TypeCode::SInt8 || t == TypeCode::SInt16 || t == TypeCode::SInt32;
}

std::optional<IntRange> type_range(TypeCode t) noexcept {
  switch (t) {
    case TypeCode::Bool:
    case TypeCode::RadioDirBit:
      return IntRange{0, 1};
    case TypeCode::UInt8:
    case TypeCode::EnumDir8:
      return IntRange{0, 0xFF};
    case TypeCode::SInt8:
      return IntRange{-128, 127};
    case TypeCode::UInt16:
    case TypeCode::RadioDir16:
    case TypeCode::EnumDir16:
      return IntRange{0, 0xFFFF};
    case TypeCode::SInt16:
      return IntRange{-32768, 32767};
    case TypeCode::UInt32:
      return IntRange{0, 0xFFFFFFFFll};
    case TypeCode::SInt32:
      return IntRange{-2147483648ll, 2147483647ll};
    default:
      return std::nullopt;
  }
}

std::optional<std::int64_t> field_integer(TypeCode t, std::uint32_t raw) noexcept {
  const unsigned bits = 8 * type_size(t);
  if (is_text_type(t) || t == TypeCode::LinFloat) return static_cast<std::int64_t>(raw);
  if (t == TypeCode::Bool || t == TypeCode::RadioDirBit)
    return raw <= 1 ? std::optional<std::int64_t>(raw) : std::nullopt;
  if (bits >= 32) {
    return is_signed_type(t) ? static_cast<std::int64_t>(static_cast<std::int32_t>(raw))
                             : static_cast<std::int64_t>(raw);
  }
  const std::uint32_t mask = (1u << bits) - 1;
  const std::uint32_t upper = raw & ~mask;
  const std::uint32_t sign = 1u << (bits - 1);
  if (upper == 0) {
    if (!is_signed_type(t)) return static_cast<std::int64_t>(raw);
    return (raw & sign) ? static_cast<std::int64_t>(raw) - (static_cast<std::int64_t>(1) << bits)
                        : static_cast<std::int64_t>(raw);
  }
  if (is_signed_type(t) && upper == ~mask && (raw & sign))
    return static_cast<std::int64_t>(static_cast<std::int32_t>(raw));
  return std::nullopt;
}

}  // namespace lmcfg
