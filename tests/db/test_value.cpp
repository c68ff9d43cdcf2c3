#include <catch2/catch.hpp>

#include "db/value.hpp"

// This file's own namespace: the test binary is a unity build (tests/CMakeLists.txt).
namespace db_test_value {

using namespace lmcfg;
using namespace lmcfg::db;

TEST_CASE("type codes follow seed 003 §10", "[db]") {
  CHECK(static_cast<int>(TypeCode::Bool) == 0x00);
  CHECK(static_cast<int>(TypeCode::CapDirlet) == 0x0F);
  for (unsigned c = 0; c <= 0x0F; ++c) {
    auto t = type_from_code(c);
    REQUIRE(t);
    CHECK(type_from_name(type_name(*t)) == t);
  }
  CHECK_FALSE(type_from_code(0x10));
  CHECK(type_from_name("SInt32") == TypeCode::SInt32);
  CHECK(type_from_name("ENUM_DIR16") == TypeCode::EnumDir16);
  CHECK_FALSE(type_from_name("UINT64"));
  CHECK(type_name(TypeCode::RadioDirBit) == "RADIO_DIR_BIT");
}

TEST_CASE("decode every type from the 4-byte field", "[db]") {
  struct Case {
    TypeCode t;
    std::uint32_t raw;
    std::int64_t expect;
  };
  const Case cases[] = {
      {TypeCode::Bool, 0xFFFFFFFE, 0},        {TypeCode::Bool, 0x00000003, 1},
      {TypeCode::UInt8, 0x123456FF, 255},     {TypeCode::SInt8, 0x000000FF, -1},
      {TypeCode::SInt8, 0xFFFFFF7F, 127},     {TypeCode::SInt8, 0x00000080, -128},
      {TypeCode::UInt16, 0xABCDFFFF, 65535},  {TypeCode::SInt16, 0x0000FFFE, -2},
      {TypeCode::SInt16, 0x00007FFF, 32767},  {TypeCode::UInt32, 0xFFFFFFFF, 4294967295ll},
      {TypeCode::SInt32, 0xFFFFFFFF, -1},     {TypeCode::SInt32, 0x000F4240, 1000000},
      {TypeCode::RadioDirBit, 0x00000001, 1}, {TypeCode::RadioDir16, 0x00010002, 2},
      {TypeCode::EnumDir8, 0x00000102, 2},    {TypeCode::EnumDir16, 0xFFFF0003, 3},
  };
  for (const auto& c : cases) {
    INFO(type_name(c.t) << " raw " << c.raw);
    auto v = decode_value(c.t, c.raw);
    CHECK(v.kind == Value::Kind::Integer);
    CHECK(v.integer == c.expect);
    CHECK(v.raw == c.raw);
  }
  for (auto t : {TypeCode::String, TypeCode::CapDir, TypeCode::Stringlet, TypeCode::CapDirlet}) {
    auto v = decode_value(t, 0x616E6E55);  // "Unna", first character in the lowest byte
    CHECK(v.kind == Value::Kind::Text);
    CHECK(v.text == "Unna");
    CHECK(decode_value(t, 0x00006564).text == "de");
  }
  CHECK(decode_value(TypeCode::LinFloat, 0x3F800000).kind == Value::Kind::Raw);
}

TEST_CASE("encode integers and text", "[db]") {
  CHECK(encode_integer(TypeCode::SInt8, -1) == 0xFFu);
  CHECK(encode_integer(TypeCode::SInt16, -2) == 0xFFFEu);
  CHECK(encode_integer(TypeCode::SInt32, -1) == 0xFFFFFFFFu);
  CHECK(encode_integer(TypeCode::Bool, 1) == 1u);
  CHECK(encode_text("Unna") == 0x616E6E55u);
  CHECK(encode_text("ab") == 0x00006261u);
  for (unsigned c = 0; c <= 0x0F; ++c) {
    auto t = *type_from_code(c);
    auto r = type_range(t);
    if (!r) continue;
    for (auto v : {r->min, r->max}) CHECK(decode_value(t, encode_integer(t, v)).integer == v);
  }
}

TEST_CASE("format values with scale, unit and labels", "[db]") {
  ValueSpec plain{TypeCode::UInt16, std::nullopt, "", {}, std::nullopt, std::nullopt};
  CHECK(format_value(plain, 16) == "16");
  ValueSpec pos{TypeCode::SInt32, 0.0001, "mm", {}, std::nullopt, std::nullopt};
  CHECK(format_value(pos, 1000000) == "100 mm");
  CHECK(format_value(pos, static_cast<std::uint32_t>(-5)) == "-0.0005 mm");
  ValueSpec vel{TypeCode::UInt32, 0.000001, "m/s", {}, std::nullopt, std::nullopt};
  CHECK(format_value(vel, 500000) == "0.5 m/s");
  ValueSpec en{
      TypeCode::EnumDir16, std::nullopt, "", {{0, "By Hex Switch S1"}, {2, "By Parameter"}}, 0, 2};
  CHECK(format_value(en, 2) == "By Parameter (2)");
  CHECK(format_value(en, 1) == "1");
  ValueSpec txt{TypeCode::Stringlet, std::nullopt, "", {}, std::nullopt, std::nullopt};
  CHECK(format_value(txt, 0x616E6E55) == "\"Unna\"");
  ValueSpec unknown{};
  CHECK(format_value(unknown, 0x1234) == "0x00001234");
  CHECK(format_scaled(200000, 0.00001) == "2");
  CHECK(format_scaled(1, 0.01) == "0.01");
}

TEST_CASE("parse user values back to raw", "[db]") {
  ValueSpec pos{TypeCode::SInt32, 0.0001, "mm", {}, -10000000, 10000000};
  CHECK(parse_value(pos, "100 mm").value() == 1000000u);
  CHECK(parse_value(pos, "100mm").value() == 1000000u);
  CHECK(parse_value(pos, "-0.5 mm").value() == static_cast<std::uint32_t>(-5000));
  CHECK(parse_value(pos, "1000000").value() == 1000000u);  // bare number = raw
  CHECK(parse_value(pos, "0xF4240").value() == 1000000u);
  CHECK(parse_value(pos, "F4240h").value() == 1000000u);
  CHECK(parse_value(pos, "-5").value() == static_cast<std::uint32_t>(-5));
  {
    auto r = parse_value(pos, "100.00005 mm");
    REQUIRE_FALSE(r);
    CHECK(r.error().message == "\"100.00005 mm\" is not a multiple of the resolution 0.0001 mm");
  }
  {
    auto r = parse_value(pos, "100 m/s");
    REQUIRE_FALSE(r);
    CHECK(r.error().code == Errc::invalid_argument);
    CHECK(r.error().message ==
          "unit \"m/s\" in \"100 m/s\" does not match the value's unit \"mm\"");
  }
  {
    auto r = parse_value(pos, "2000 mm");
    REQUIRE_FALSE(r);
    CHECK(r.error().code == Errc::validation_failed);
    CHECK(r.error().message == "value 20000000 (2000 mm) is above the maximum 10000000 (1000 mm)");
  }
  {
    auto r = parse_value(pos, "1.5");
    REQUIRE_FALSE(r);
    CHECK(r.error().message ==
          "\"1.5\" has decimals but no unit: a bare number is a raw value; write it as \"1.5 mm\"");
  }
  ValueSpec acc{TypeCode::UInt32, 0.00001, "m/s^2", {}, std::nullopt, std::nullopt};
  CHECK(parse_value(acc, "2 m/s2").value() == 200000u);  // '^' optional
  CHECK(parse_value(acc, "2 m/s^2").value() == 200000u);

  ValueSpec en{
      TypeCode::EnumDir16, std::nullopt, "", {{0, "By Hex Switch S1"}, {2, "By Parameter"}}, 0, 2};
  CHECK(parse_value(en, "by parameter").value() == 2u);
  CHECK(parse_value(en, "By Parameter (2)").value() == 2u);
  CHECK(parse_value(en, "0").value() == 0u);
  {
    auto r = parse_value(en, "Sometimes");
    REQUIRE_FALSE(r);
    CHECK(r.error().message ==
          "cannot read \"Sometimes\": expected a raw number, a value with unit or one of the "
          "labels \"By Hex Switch S1\", "
          "\"By Parameter\"");
  }
  ValueSpec s8{TypeCode::SInt8, std::nullopt, "", {}, std::nullopt, std::nullopt};
  CHECK(parse_value(s8, "-1").value() == 0xFFu);
  {
    auto r = parse_value(s8, "200");
    REQUIRE_FALSE(r);
    CHECK(r.error().message == "value 200 is outside the SINT8 range -128..127");
  }
  ValueSpec b{TypeCode::Bool, std::nullopt, "", {}, std::nullopt, std::nullopt};
  CHECK(parse_value(b, "1").value() == 1u);
  CHECK_FALSE(parse_value(b, "2"));
  ValueSpec u16{TypeCode::UInt16, std::nullopt, "", {}, std::nullopt, std::nullopt};
  CHECK(parse_value(u16, "65535").value() == 0xFFFFu);
  CHECK_FALSE(parse_value(u16, "-1"));
  CHECK_FALSE(parse_value(u16, "65536"));
  CHECK_FALSE(parse_value(u16, ""));
  ValueSpec txt{TypeCode::Stringlet, std::nullopt, "", {}, std::nullopt, std::nullopt};
  CHECK(parse_value(txt, "\"Unna\"").value() == 0x616E6E55u);
  CHECK(parse_value(txt, "de").value() == 0x00006564u);
  CHECK_FALSE(parse_value(txt, "toolong"));
}

TEST_CASE("range checks against type and min/max", "[db]") {
  ValueSpec s{TypeCode::SInt16, 0.1, "V", {}, -100, 500};
  CHECK(check_range(s, 500).ok());
  CHECK(check_range(s, -100).ok());
  auto lo = check_range(s, -101);
  REQUIRE_FALSE(lo);
  CHECK(lo.error().message == "value -101 (-10.1 V) is below the minimum -100 (-10 V)");
  auto ty = check_range(s, 40000);
  REQUIRE_FALSE(ty);
  CHECK(ty.error().message == "value 40000 is outside the SINT16 range -32768..32767");
}

}  // namespace db_test_value
