// The drive family table (lib/common/families.cpp): LinRS 3V27 §11-§12, p26,
// p32; LinRS 3.23 p53; DCF p8; the C1250 notes.
#include <catch2/catch.hpp>

#include "common/families.hpp"

// This file's own namespace: the test binary is a unity build (tests/CMakeLists.txt).
namespace common_test_families {

using namespace lmcfg;

TEST_CASE("drive families: what each has", "[families]") {
  CHECK(families::names() == "E1100, B1100, C1100, E1200, E1400");
  const auto& e = families::reference();
  CHECK(e.name == "E1100");
  CHECK(e.profile == "e1100-mc-linrs");
  CHECK((e.curves && e.command_table && e.flash_save && e.stored_defaults));
  CHECK(e.curve_limit == 100);

  // LinRS 3V27 §11-§12 "not on B1100"; DCF p8: defaults not stored; 16 curves.
  const auto* b = families::find("b1100");
  REQUIRE(b);
  CHECK(b->name == "B1100");
  CHECK_FALSE(b->curves);
  CHECK_FALSE(b->command_table);
  CHECK_FALSE(b->stored_defaults);
  CHECK(b->curve_limit == 16);
  CHECK(b->macid.find("6081h") != std::string_view::npos);

  // LinRS 3V27 p32: C1100 curve/CT add and delete act on flash; no save.
  const auto* c = families::find("C1100");
  REQUIRE(c);
  CHECK(c->curves);
  CHECK(c->command_table);
  CHECK_FALSE(c->flash_save);
  CHECK(c->curve_limit == 50);

  for (const char* n : {"E1200", "E1400"}) {
    const auto* f = families::find(n);
    REQUIRE(f);
    CHECK(f->profile == "e1200-mc-linrs");
    CHECK(f->curve_limit == 100);
    CHECK(f->flash_save);
  }
  CHECK(families::find("E9999") == nullptr);
  CHECK(families::find("") == nullptr);
}

TEST_CASE("drive family names: parsed case-insensitively, an unknown one refused with the list",
          "[families]") {
  auto none = families::parse("", "--family");
  REQUIRE(none.ok());
  CHECK(*none == nullptr);
  auto c = families::parse("c1100", "--family");
  REQUIRE(c.ok());
  CHECK((*c)->name == "C1100");
  auto bad = families::parse("X9", "inventory.toml:7");
  REQUIRE_FALSE(bad.ok());
  CHECK(bad.error().message ==
        "inventory.toml:7: unknown drive family 'X9'; expected one of E1100, B1100, C1100, E1200, "
        "E1400 (docs/families.md)");
}

}  // namespace common_test_families
