// The one comparison (lib/ops/compare.cpp): the default rule, typed rows of
// parameters, curves and command table entries, each reason and each way a
// side's unlisted UPID is resolved.
#include <catch2/catch.hpp>

#include "db/database.hpp"
#include "ops/compare.hpp"
#include "ops/restore.hpp"

// This file's own namespace: the test binary is a unity build (tests/CMakeLists.txt).
namespace ops_test_compare {

using namespace lmcfg;
using ops::Reason;
using State = ops::ParamValue::State;

namespace {

const db::Database& real_db() {
  static auto db = db::Database::open(LMCFG_DB_PATH);
  REQUIRE(db.ok());
  return *db;
}

config::Parameter param(std::uint16_t upid, std::uint32_t value,
                        std::optional<std::uint32_t> def = std::nullopt,
                        std::optional<std::uint8_t> type = std::nullopt) {
  return config::Parameter{upid, value, type, def, {}, {}, {}};
}

ops::ParamSide side(const std::vector<config::Parameter>& v,
                    config::ParamSet listed = config::ParamSet::modified,
                    ops::Resolve resolve = ops::Resolve::rule_then_ask, ops::AskValue ask = {}) {
  return ops::ParamSide{&v, listed, resolve, std::move(ask)};
}

ops::ParamRow only_row(const ops::ParamCompare& c) {
  REQUIRE(c.rows.size() == 1);
  return c.rows.front();
}

}  // namespace

TEST_CASE("seed003 §10.2 compare: the default rule is the database's default, else the recorded",
          "[compare]") {
  // upid-db/parameters.tsv: 13A2h has the default 15.
  const auto from_db = ops::default_of(real_db(), 0x13A2, 7);
  CHECK(from_db.value == 15u);
  CHECK(from_db.source == ops::DefaultSource::database);
  const auto recorded = ops::default_of(db::Database::empty(), 0x13A2, 7);
  CHECK(recorded.value == 7u);
  CHECK(recorded.source == ops::DefaultSource::recorded);
  const auto none = ops::default_of(db::Database::empty(), 0x13A2, std::nullopt);
  CHECK_FALSE(none.value);
  CHECK(none.source == ops::DefaultSource::none);
}

TEST_CASE("seed003 §10.2 compare: a UPID a modified-only side does not list holds its default",
          "[compare]") {
  const std::vector<config::Parameter> none;
  {  // the database's default differs from A's value: a difference
    const std::vector<config::Parameter> a{param(0x13A2, 20)};
    auto c = ops::compare_parameters(2, side(a), side(none), real_db());
    REQUIRE(c.ok());
    const auto row = only_row(*c);
    CHECK(row.layer == 2);
    CHECK(row.upid == 0x13A2);
    CHECK(row.reason == Reason::differs);
    CHECK(row.differs());
    CHECK(row.a.state == State::value);
    CHECK(row.a.value == 20u);
    CHECK(row.a.record == &a.front());
    CHECK(row.b.state == State::at_default);
    CHECK(row.b.value == 15u);
    CHECK(row.b.source == ops::DefaultSource::database);
    CHECK(row.b.record == nullptr);
    CHECK(c->defaults_recorded == 0);
  }
  {  // A holds the default: the same
    const std::vector<config::Parameter> a{param(0x13A2, 15)};
    auto c = ops::compare_parameters(2, side(a), side(none), real_db());
    REQUIRE(c.ok());
    CHECK(only_row(*c).reason == Reason::same);
    CHECK_FALSE(only_row(*c).differs());
  }
  {  // no database: the default a side recorded (B's record, A unlisted)
    const std::vector<config::Parameter> b{param(0x1100, 3, 3)};
    auto c = ops::compare_parameters(2, side(none), side(b), db::Database::empty());
    REQUIRE(c.ok());
    const auto row = only_row(*c);
    CHECK(row.reason == Reason::same);
    CHECK(row.a.state == State::at_default);
    CHECK(row.a.source == ops::DefaultSource::recorded);
    CHECK(c->defaults_recorded == 1);
  }
  {  // the default unknown and nothing to ask: only in B
    const std::vector<config::Parameter> b{param(0x1100, 3)};
    auto c = ops::compare_parameters(2, side(none), side(b), db::Database::empty());
    REQUIRE(c.ok());
    const auto row = only_row(*c);
    CHECK(row.reason == Reason::only_in_b);
    CHECK_FALSE(row.a.value);
    CHECK(row.def.source == ops::DefaultSource::none);
  }
}

TEST_CASE("seed003 §10.3 compare: a UPID a full side does not list is not ROM-writable there",
          "[compare]") {
  const std::vector<config::Parameter> a{param(0x13A2, 15)}, none;
  auto c = ops::compare_parameters(2, side(a), side(none, config::ParamSet::full), real_db());
  REQUIRE(c.ok());
  const auto row = only_row(*c);
  // The default is looked up (it is shown and counted), but a UPID that is not
  // ROM-writable has no value to compare with.
  CHECK(row.def.value == 15u);
  CHECK(row.b.state == State::not_writable);
  CHECK_FALSE(row.b.value);
  CHECK(row.reason == Reason::only_in_a);
}

TEST_CASE("seed003 §10 compare: recorded types that differ are a difference with equal values",
          "[compare]") {
  const std::vector<config::Parameter> a{param(0x1100, 5, std::nullopt, 0x03)};
  const std::vector<config::Parameter> b{param(0x1100, 5, std::nullopt, 0x04)};
  auto c = ops::compare_parameters(2, side(a), side(b), db::Database::empty());
  REQUIRE(c.ok());
  const auto row = only_row(*c);
  CHECK(row.reason == Reason::same);
  CHECK(row.type_differs);
  CHECK(row.differs());
}

TEST_CASE("seed003 §10 05h 01h compare: each way an unlisted UPID is resolved", "[compare]") {
  const std::vector<config::Parameter> file{param(0x13A2, 15), param(0x13A3, 9, 4)}, none;
  std::vector<std::uint16_t> asked;
  ops::AskValue rom = [&](std::uint16_t upid) -> Result<std::optional<std::uint32_t>> {
    asked.push_back(upid);
    return std::optional<std::uint32_t>(upid == 0x13A2 ? 15u : 9u);
  };
  SECTION("ask: always asked, the rule never consulted (verify)") {
    auto c = ops::compare_parameters(2, side(file, config::ParamSet::modified, ops::Resolve::none),
                                     side(none, config::ParamSet::modified, ops::Resolve::ask, rom),
                                     real_db());
    REQUIRE(c.ok());
    CHECK(asked == std::vector<std::uint16_t>{0x13A2, 0x13A3});
    REQUIRE(c->rows.size() == 2);
    for (const auto& row : c->rows) {
      CHECK(row.reason == Reason::same);
      CHECK(row.b.source == ops::DefaultSource::asked);
      CHECK(row.def.source == ops::DefaultSource::none);
    }
  }
  SECTION("rule_if_differs: the rule where it shows a difference, else asked (plan)") {
    auto c = ops::compare_parameters(
        2, side(none, config::ParamSet::modified, ops::Resolve::rule_if_differs, rom),
        side(file, config::ParamSet::modified, ops::Resolve::none), real_db());
    REQUIRE(c.ok());
    // 13A2h: the database's default 15 equals the file's value: asked.
    // 13A3h: the recorded default 4 differs from the file's 9: not asked.
    CHECK(asked == std::vector<std::uint16_t>{0x13A2});
    REQUIRE(c->rows.size() == 2);
    CHECK(c->rows[0].reason == Reason::same);
    CHECK(c->rows[0].a.source == ops::DefaultSource::asked);
    CHECK(c->rows[1].reason == Reason::differs);
    CHECK(c->rows[1].a.value == 4u);
    CHECK(c->rows[1].a.source == ops::DefaultSource::recorded);
  }
  SECTION("none: an unlisted UPID is only on the other side (a leftover)") {
    auto c = ops::compare_parameters(2, side(file, config::ParamSet::modified, ops::Resolve::none),
                                     side(none, config::ParamSet::modified, ops::Resolve::none),
                                     real_db());
    REQUIRE(c.ok());
    CHECK(asked.empty());
    for (const auto& row : c->rows) CHECK(row.reason == Reason::only_in_a);
  }
  SECTION("rule_then_ask: asked only where the rule knows nothing (diff)") {
    const std::vector<config::Parameter> unknown{param(0x1100, 1)};
    auto c = ops::compare_parameters(
        2, side(unknown), side(none, config::ParamSet::modified, ops::Resolve::rule_then_ask, rom),
        db::Database::empty());
    REQUIRE(c.ok());
    CHECK(asked == std::vector<std::uint16_t>{0x1100});
    CHECK(only_row(*c).reason == Reason::differs);
    CHECK(only_row(*c).def.source == ops::DefaultSource::asked);
    CHECK(c->defaults_asked == 1);
  }
}

TEST_CASE("compare: a failed read of a side's value fails the comparison", "[compare]") {
  const std::vector<config::Parameter> file{param(0x13A2, 15)}, none;
  ops::AskValue broken = [](std::uint16_t) -> Result<std::optional<std::uint32_t>> {
    return Error(Errc::timeout, "no answer from MACID 11h");
  };
  auto c = ops::compare_parameters(
      2, side(file, config::ParamSet::modified, ops::Resolve::none),
      side(none, config::ParamSet::modified, ops::Resolve::ask, broken), real_db());
  REQUIRE_FALSE(c.ok());
  CHECK(c.error().message == "no answer from MACID 11h");
}

TEST_CASE("seed003 §11 §12 compare: curves and command table entries by ID and raw content",
          "[compare]") {
  const std::vector<config::Curve> a{{1, {1, 2}, {3}}, {2, {1}, {}}, {3, {9}, {9}}};
  const std::vector<config::Curve> b{{1, {1, 2}, {3}}, {2, {1}, {7}}, {4, {9}, {9}}};
  const auto curves = ops::compare_curves(a, b);
  REQUIRE(curves.size() == 3);
  CHECK(curves[0].id == 2);
  CHECK(curves[0].reason == Reason::differs);
  CHECK(curves[0].a == &a[1]);
  CHECK(curves[0].b == &b[1]);
  CHECK(curves[1].id == 3);
  CHECK(curves[1].reason == Reason::only_in_a);
  CHECK(curves[1].b == nullptr);
  CHECK(curves[2].id == 4);
  CHECK(curves[2].reason == Reason::only_in_b);
  CHECK(curves[2].a == nullptr);

  // The first record of an ID counts, as DriveConfig::find_ct_entry finds it.
  const std::vector<config::CtEntry> ea{{5, {1}}, {5, {2}}}, eb{{5, {1}}};
  CHECK(ops::compare_ct_entries(ea, eb).empty());
  CHECK(ops::compare_ct_entries(eb, {}).front().reason == Reason::only_in_a);
}

TEST_CASE("compare: each reason has one display text", "[compare]") {
  CHECK(std::string(ops::reason_text(Reason::same)) == "same");
  CHECK(std::string(ops::reason_text(Reason::differs)) == "differs");
  CHECK(std::string(ops::reason_text(Reason::only_in_a)) == "only in A");
  CHECK(std::string(ops::reason_text(Reason::only_in_b)) == "only in B");
  // The plan's write reasons, as plan_json and the plan's text show them.
  using W = ops::WriteReason;
  CHECK(std::string(ops::write_reason_text(W::differs)) == "differs");
  CHECK(std::string(ops::write_reason_text(W::leftover)) == "leftover back to its default");
  CHECK(std::string(ops::write_reason_text(W::again_after_defaulting)) == "again after defaulting");
  CHECK(std::string(ops::write_reason_text(W::kept_communication)) == "kept communication value");
}

}  // namespace ops_test_compare
