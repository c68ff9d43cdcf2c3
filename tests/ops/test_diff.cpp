// diff (lib/ops/diff.cpp) through the one comparison: invalid values, type
// and scope differences, and the default rule (database, the capture's
// record, the drive asked) with the notes that say where defaults came from.
#include <catch2/catch.hpp>
#include <string>

#include "db/database.hpp"
#include "ops/diff.hpp"
#include "test_config_support.hpp"

// This file's own namespace: the test binary is a unity build (tests/CMakeLists.txt).
namespace ops_test_diff {

using namespace lmcfg;
using namespace lmcfg::config;
using namespace lmcfg::config::testing;

namespace {

Parameter typed(std::uint16_t upid, std::uint32_t value, std::uint8_t type) {
  Parameter p = param(upid, value);
  p.type = type;
  return p;
}

const ops::DiffItem* item(const ops::DiffResult& r, ops::DiffItem::Kind k) {
  for (const auto& it : r.items)
    if (it.kind == k) return &it;
  return nullptr;
}

}  // namespace

TEST_CASE(
    "seed003 §9 §10 diff: a value that does not fit its type is flagged on its side, never "
    "truncated",
    "[diff]") {
  DriveConfig a, b;
  a.layer(2).push_back(typed(0x13A2, 70000, 3));  // UINT16 (§10 type 03h)
  b.layer(2).push_back(typed(0x13A2, 15, 3));
  auto r = ops::diff(a, b, db::Database::empty(), {}, {});
  REQUIRE_FALSE(r.identical());
  const auto* it = item(r, ops::DiffItem::Kind::parameter);
  REQUIRE(it != nullptr);
  CHECK(it->a == "70000 (00011170h) INVALID: does not fit type UINT16");
  CHECK(it->a_invalid == "does not fit type UINT16");
  CHECK(it->b == "15");
  CHECK(it->b_invalid.empty());
  CHECK(ops::render_text(r, "a.json", "b.json")
            .find("  13A2h (name unknown): 70000 (00011170h) INVALID: does not fit type UINT16 -> "
                  "15\n") != std::string::npos);
  // The same invalid value on both sides: no difference, but said.
  auto same = ops::diff(a, a, db::Database::empty(), {}, {});
  CHECK(same.identical());
  REQUIRE(same.notes.size() == 1);
  CHECK(same.notes[0] ==
        "MC 13A2h: both sides hold the invalid value 70000 (00011170h) INVALID: does not fit "
        "type UINT16");
  // SINT16 -5 may travel sign-extended: valid.
  DriveConfig s;
  s.layer(2).push_back(typed(0x13A2, 0xFFFFFFFB, 4));
  auto sr = ops::diff(s, b, db::Database::empty(), {}, {});
  REQUIRE(item(sr, ops::DiffItem::Kind::parameter) != nullptr);
  CHECK(item(sr, ops::DiffItem::Kind::parameter)->a_invalid.empty());
}

TEST_CASE("seed003 §10 diff: a recorded type that differs is a difference", "[diff]") {
  DriveConfig a, b;
  a.layer(2).push_back(typed(0x13A2, 16, 3));  // UINT16
  b.layer(2).push_back(typed(0x13A2, 16, 4));  // SINT16
  auto r = ops::diff(a, b, db::Database::empty(), {}, {});
  REQUIRE_FALSE(r.identical());
  const auto* it = item(r, ops::DiffItem::Kind::parameter);
  REQUIRE(it != nullptr);
  CHECK(it->detail == "type UINT16 -> SINT16");
  CHECK(it->a_type == "UINT16");
  CHECK(it->b_type == "SINT16");
  CHECK(ops::render_text(r, "a", "b")
            .find("13A2h (name unknown): 16 -> 16 (type UINT16 -> SINT16)") != std::string::npos);
}

TEST_CASE("seed003 §10.2 §11 §12 diff: a scope one side lacks is stated and is a difference",
          "[diff]") {
  DriveConfig full, partial;
  full.layer(1).push_back(param(0x0010, 1));
  full.curves.push_back(Curve{1, sinrise_info(), sinrise_data()});
  partial.scope.layers = {false, true, false, false};
  partial.scope.curves = false;
  auto r = ops::diff(full, partial, db::Database::empty(), {}, {});
  CHECK_FALSE(r.identical());
  std::size_t scope_items = 0;
  for (const auto& it : r.items) scope_items += it.kind == ops::DiffItem::Kind::scope ? 1 : 0;
  CHECK(scope_items == 4);  // OS, Intf, Appl, curves
  const auto text = ops::render_text(r, "full.json", "partial.json");
  CHECK(text.rfind("--- full.json (modified parameters of OS, MC, Intf, Appl; curves; command "
                   "table)\n+++ partial.json (modified parameters of MC; no curves; command "
                   "table)\ncompared: modified parameters of MC; no curves; command table\n",
                   0) == 0);
  CHECK(text.find("  layer OS: captured -> not captured (1 parameter(s) on the A side not "
                  "compared)\n") != std::string::npos);
  CHECK(text.find("  curves: captured -> not captured (1 curve(s) on the A side not compared)\n") !=
        std::string::npos);
  CHECK(text.find("\nidentical\n") == std::string::npos);
  // Factory defaults take the other side's scope: nothing lacking.
  auto d = ops::diff(ops::factory_defaults_config(partial.scope), partial, db::Database::empty(),
                     {}, ops::DiffOptions{true, false});
  CHECK(d.identical());
}

TEST_CASE(
    "LinRS §16.1 diff: a side whose drive has no curve or command table group says so, and two "
    "such sides are identical",
    "[diff][families]") {
  DriveConfig e1100, b1100;
  e1100.curves.push_back(Curve{1, sinrise_info(), sinrise_data()});
  b1100.scope.curves = false;
  b1100.scope.command_table = false;
  b1100.scope.drive_lacks = {"curves", "command_table"};
  auto r = ops::diff(e1100, b1100, db::Database::empty(), {}, {});
  CHECK_FALSE(r.identical());
  const auto text = ops::render_text(r, "e1100.json", "b1100.json");
  CHECK(text.find("  curves: captured -> not captured: the drive has no such group (1 curve(s) "
                  "on the A side not compared)\n") != std::string::npos);
  CHECK(text.find("  command table: captured -> not captured: the drive has no such group") !=
        std::string::npos);
  CHECK(ops::diff(b1100, b1100, db::Database::empty(), {}, {}).identical());
}

TEST_CASE("seed003 §10.2 diff: a UPID one side does not list compares with its default", "[diff]") {
  DriveConfig a, b;
  Parameter p = param(0x13A2, 16);
  p.default_value = 15;  // recorded at backup (05h 07h)
  a.layer(2).push_back(p);
  auto r = ops::diff(a, b, db::Database::empty(), {}, {});
  const auto* it = item(r, ops::DiffItem::Kind::parameter);
  REQUIRE(it != nullptr);
  CHECK(it->a == "16 (0010h)");
  CHECK(it->b == "default 15 (000Fh)");
  CHECK(r.notes == std::vector<std::string>{
                       "1 default value(s) the UPID database does not know were taken from the "
                       "capture (the drive's own, recorded at backup)"});
  // The recorded default equal to the value: identical.
  a.layer(2).front().value = 15;
  CHECK(ops::diff(a, b, db::Database::empty(), {}, {}).identical());
  // Nothing recorded: asked (the tools ask a connected drive), said in a note.
  DriveConfig c;
  c.layer(2).push_back(param(0x13A2, 16));
  std::vector<std::uint16_t> asked;
  const ops::DefaultLookup lookup = [&](std::uint16_t upid) -> std::optional<std::uint32_t> {
    asked.push_back(upid);
    return 16;
  };
  auto l = ops::diff(c, b, db::Database::empty(), lookup, {});
  CHECK(asked == std::vector<std::uint16_t>{0x13A2});
  CHECK(l.identical());
  CHECK(l.notes == std::vector<std::string>{"1 default value(s) the UPID database does not know "
                                            "were asked from the drive (05h 07h)"});
  // Unknown everywhere: a difference against "default".
  auto u = ops::diff(c, b, db::Database::empty(), {}, {});
  REQUIRE(item(u, ops::DiffItem::Kind::parameter) != nullptr);
  CHECK(item(u, ops::DiffItem::Kind::parameter)->b == "default");
}

}  // namespace ops_test_diff
