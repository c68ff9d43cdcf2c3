// Byte helpers (lib/common/bytes.cpp): little-endian fields, hex text both
// ways, numbers as users write them. LinRS §4: "Data are transmitted lowest
// byte first highest byte last."
#include <catch2/catch.hpp>

#include "common/bytes.hpp"

// This file's own namespace: the test binary is a unity build (tests/CMakeLists.txt).
namespace common_test_bytes {

using namespace lmcfg;

TEST_CASE("LinRS §9.1 bytes: little-endian fields of the read RAM capture", "[common][bytes]") {
  // LinRS §9.1 "Tx: 01 11 05 02 00 03 A2 13 04": UPID 13A2h lowest byte first.
  const Bytes tx = *from_hex("01 11 05 02 00 03 A2 13 04");
  CHECK(get_u16le(tx, 6) == 0x13A2);
  // LinRS §10.1 default of 13A2h: "0F 00 00 00" = 15.
  const Bytes def = *from_hex("0F 00 00 00");
  CHECK(get_u32le(def, 0) == 15);
  Bytes out;
  put_u16le(out, 0x13A2);
  put_u32le(out, 0x000E113E);
  CHECK(to_hex(out) == "A2 13 3E 11 0E 00");
  CHECK(get_u32le(out, 2) == 0x000E113E);
}

TEST_CASE("bytes: hex text, either way", "[common][bytes]") {
  CHECK(to_hex(Bytes{0x01, 0xAB, 0x0F}) == "01 AB 0F");
  CHECK(to_hex(Bytes{0x01, 0xAB}, '\0') == "01AB");
  CHECK(to_hex(Bytes{0x01, 0xAB}, ':') == "01:AB");
  CHECK(to_hex(Bytes{}) == "");
  CHECK(hex(0x13A2, 4) == "13A2");
  CHECK(hex(0x11, 2, "h") == "11h");
  CHECK(hex(0x5, 4) == "0005");
  CHECK(hex(0x12345, 4) == "12345");  // never truncated
  CHECK(hex(0, 0) == "0");
  CHECK(hex(0xFFFFFFFF, 2) == "FFFFFFFF");
  CHECK(hex_digit_value('7') == 7);
  CHECK(hex_digit_value('a') == 10);
  CHECK(hex_digit_value('F') == 15);
  CHECK(hex_digit_value('g') == -1);
  CHECK(hex_digit_value(' ') == -1);
  CHECK(from_hex("01 11:05\n02\t0A\r\n") == std::optional<Bytes>(Bytes{1, 0x11, 5, 2, 0x0A}));
  CHECK(from_hex("0111") == std::optional<Bytes>(Bytes{1, 0x11}));
  CHECK(from_hex("") == std::optional<Bytes>(Bytes{}));
  CHECK_FALSE(from_hex("011"));   // odd count
  CHECK_FALSE(from_hex("0 11"));  // a lone nibble before a separator
  CHECK_FALSE(from_hex("0x11"));  // not hex
  CHECK(as_bytes("S4\r").size() == 3);
  CHECK(to_hex(as_bytes("S4\r")) == "53 34 0D");
}

TEST_CASE("bytes: numbers as users write them, case-insensitive names", "[common][bytes]") {
  CHECK(parse_number("0x13A2", false) == std::optional<std::uint32_t>(0x13A2));
  CHECK(parse_number("13a2h", false) == std::optional<std::uint32_t>(0x13A2));
  CHECK(parse_number("13A2", true) == std::optional<std::uint32_t>(0x13A2));
  CHECK(parse_number("5026", false) == std::optional<std::uint32_t>(5026));
  CHECK(parse_number("4294967295", false) == std::optional<std::uint32_t>(0xFFFFFFFF));
  CHECK(parse_number("FFFFFFFF", true) == std::optional<std::uint32_t>(0xFFFFFFFF));
  CHECK_FALSE(parse_number("4294967296", false));
  CHECK_FALSE(parse_number("100000000", true));  // nine hex digits
  CHECK_FALSE(parse_number("13A2", false));      // decimal unless marked
  CHECK_FALSE(parse_number("", false));
  CHECK_FALSE(parse_number("h", false));
  CHECK_FALSE(parse_number("0x", false));
  CHECK_FALSE(parse_number("-1", false));
  CHECK(iequals("uint16", "UINT16"));
  CHECK_FALSE(iequals("uint16", "UINT8"));
  CHECK_FALSE(iequals("ab", "abc"));
}

}  // namespace common_test_bytes
