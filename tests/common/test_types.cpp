// Parameter type codes (lib/common/types.cpp). LinRS §10 "Supported Parameter
// Types": 00h BOOL 1 bit, 01h UINT8 8, 02h SINT8 8, 03h UINT16 16, 04h SINT16
// 16, 05h UINT32 32, 06h SINT32 32, 07h LIN_FLOAT 32 ("not used as
// parameter"), 08h STRING, 09h CAP_DIR, 0Ah RADIO_DIR_BIT 1, 0Bh RADIO_DIR16
// 16, 0Ch ENUM_DIR8 8, 0Dh ENUM_DIR16 16, 0Eh STRINGLET 32 and 0Fh CAP_DIRLET
// 32 ("Part of String 4 Characters"). LinRS §9: "All parameters values are
// mapped in a 4 byte value memory area."
#include <catch2/catch.hpp>

#include "common/types.hpp"

// This file's own namespace: the test binary is a unity build (tests/CMakeLists.txt).
namespace common_test_types {

using namespace lmcfg;

TEST_CASE("LinRS §10 Supported Parameter Types: codes, names and sizes of the table",
          "[common][types]") {
  struct Row {
    unsigned code;
    const char* name;
    unsigned bytes;  // the value's bytes in the 4-byte field (1 for one bit)
  };
  const Row table[] = {{0x00, "BOOL", 1},      {0x01, "UINT8", 1},         {0x02, "SINT8", 1},
                       {0x03, "UINT16", 2},    {0x04, "SINT16", 2},        {0x05, "UINT32", 4},
                       {0x06, "SINT32", 4},    {0x07, "LIN_FLOAT", 4},     {0x08, "STRING", 4},
                       {0x09, "CAP_DIR", 4},   {0x0A, "RADIO_DIR_BIT", 1}, {0x0B, "RADIO_DIR16", 2},
                       {0x0C, "ENUM_DIR8", 1}, {0x0D, "ENUM_DIR16", 2},    {0x0E, "STRINGLET", 4},
                       {0x0F, "CAP_DIRLET", 4}};
  for (const auto& r : table) {
    INFO(r.name);
    auto t = type_from_code(r.code);
    REQUIRE(t);
    CHECK(type_code(*t) == r.code);
    CHECK(type_name(*t) == r.name);
    CHECK(type_from_name(r.name) == t);
    CHECK(type_size(*t) == r.bytes);
  }
  CHECK_FALSE(type_from_code(0x10));
  CHECK(type_from_name("uint16") == TypeCode::UInt16);
  CHECK(type_from_name("Enum_Dir16") == TypeCode::EnumDir16);
  CHECK_FALSE(type_from_name("UINT64"));
  CHECK_FALSE(type_from_name(""));
}

TEST_CASE("LinRS §10 types: text, signed and the ranges of the integer types", "[common][types]") {
  for (auto t : {TypeCode::String, TypeCode::CapDir, TypeCode::Stringlet, TypeCode::CapDirlet})
    CHECK(is_text_type(t));
  CHECK_FALSE(is_text_type(TypeCode::UInt32));
  CHECK_FALSE(is_text_type(TypeCode::LinFloat));
  for (auto t : {TypeCode::SInt8, TypeCode::SInt16, TypeCode::SInt32}) CHECK(is_signed_type(t));
  CHECK_FALSE(is_signed_type(TypeCode::UInt32));
  CHECK_FALSE(is_signed_type(TypeCode::LinFloat));

  auto range = [](TypeCode t) {
    auto r = type_range(t);
    REQUIRE(r);
    return std::pair<std::int64_t, std::int64_t>(r->min, r->max);
  };
  using P = std::pair<std::int64_t, std::int64_t>;
  CHECK(range(TypeCode::Bool) == P(0, 1));
  CHECK(range(TypeCode::RadioDirBit) == P(0, 1));
  CHECK(range(TypeCode::UInt8) == P(0, 255));
  CHECK(range(TypeCode::EnumDir8) == P(0, 255));
  CHECK(range(TypeCode::SInt8) == P(-128, 127));
  CHECK(range(TypeCode::UInt16) == P(0, 65535));
  CHECK(range(TypeCode::RadioDir16) == P(0, 65535));
  CHECK(range(TypeCode::EnumDir16) == P(0, 65535));
  CHECK(range(TypeCode::SInt16) == P(-32768, 32767));
  CHECK(range(TypeCode::UInt32) == P(0, 4294967295LL));
  CHECK(range(TypeCode::SInt32) == P(-2147483648LL, 2147483647LL));
  CHECK_FALSE(type_range(TypeCode::LinFloat));
  CHECK_FALSE(type_range(TypeCode::String));
  CHECK_FALSE(type_range(TypeCode::Stringlet));
}

TEST_CASE("LinRS §10 types: the integer a 4-byte field holds, or none when it does not fit",
          "[common][types]") {
  // §10.1: 13A2h (UINT16) reads 0000000Fh: 15.
  CHECK(field_integer(TypeCode::UInt16, 0x0000000F) == 15);
  CHECK(field_integer(TypeCode::UInt16, 0x0000FFFF) == 65535);
  CHECK_FALSE(field_integer(TypeCode::UInt16, 0x00010000));
  // Signed values: their own width, or sign-extended to 32 bits.
  CHECK(field_integer(TypeCode::SInt16, 0x0000FFFF) == -1);
  CHECK(field_integer(TypeCode::SInt16, 0xFFFFFFFF) == -1);
  CHECK(field_integer(TypeCode::SInt16, 0xFFFF8000) == -32768);
  CHECK_FALSE(field_integer(TypeCode::SInt16, 0xFFFF0001));  // upper bytes without the sign
  CHECK_FALSE(field_integer(TypeCode::SInt16, 0x00018000));
  CHECK(field_integer(TypeCode::SInt8, 0x00000080) == -128);
  CHECK(field_integer(TypeCode::SInt8, 0x0000007F) == 127);
  CHECK(field_integer(TypeCode::SInt8, 0xFFFFFF80) == -128);
  CHECK_FALSE(field_integer(TypeCode::UInt8, 0x00000100));
  CHECK(field_integer(TypeCode::SInt32, 0x80000000) == -2147483648LL);
  CHECK(field_integer(TypeCode::UInt32, 0x80000000) == 2147483648LL);
  // One bit: 0 or 1 only.
  CHECK(field_integer(TypeCode::Bool, 1) == 1);
  CHECK_FALSE(field_integer(TypeCode::Bool, 2));
  CHECK_FALSE(field_integer(TypeCode::RadioDirBit, 0x100));
  // Text and LIN_FLOAT fields are their raw 32 bits.
  CHECK(field_integer(TypeCode::Stringlet, 0x6E6E6155) == 0x6E6E6155);
  CHECK(field_integer(TypeCode::LinFloat, 0xFFFFFFFF) == 0xFFFFFFFFLL);
}

}  // namespace common_test_types
