// One parameter's description for `lmcfg get/set` (lib/ops/param_info.cpp):
// the database's, with what it lacks asked from the drive (LinRS §10 05h
// 04h/05h/06h): against the manual's own conversation and the simulated drive.
#include <catch2/catch.hpp>

#include "common/types.hpp"
#include "e2e_support.hpp"
#include "manual_client.hpp"
#include "ops/param_info.hpp"

// This file's own namespace: the test binary is a unity build (tests/CMakeLists.txt).
namespace ops_test_param_info {

using namespace lmcfg;

namespace {

db::Parameter known(std::optional<db::TypeCode> type, std::optional<std::int64_t> min,
                    std::optional<std::int64_t> max) {
  db::Parameter p;
  p.upid = 0x13A2;
  p.layer = db::Layer::MC;
  p.spec.type = type;
  p.spec.min = min;
  p.spec.max = max;
  return p;
}

sim::Parameter sim_param(std::uint16_t upid, db::TypeCode type, std::uint32_t min,
                         std::uint32_t max) {
  sim::Parameter p;
  p.upid = upid;
  p.type = type_code(type);
  p.min = min;
  p.max = max;
  return p;
}

}  // namespace

TEST_CASE("param_info: LinRS §10.1 type, min and max of 13A2h asked when the database lacks it",
          "[param_info][golden]") {
  // LinRS §10.1 "Get UPID type": 03h = UINT16; "Get min value": 0; "Get max value": FFFFh.
  test::ManualClient f(944, 958);
  auto d = ops::describe_parameter(f.client, 0x13A2, nullptr, true);
  REQUIRE(d.ok());
  CHECK(d->spec.type == db::TypeCode::UInt16);
  CHECK(d->spec.min == 0);
  CHECK(d->spec.max == 0xFFFF);
  CHECK(d->asked == "type UINT16, min, max");
  f.done();
}

TEST_CASE("param_info: LinRS §10.1 only the type without with_range", "[param_info][golden]") {
  test::ManualClient f(944, 946);
  auto d = ops::describe_parameter(f.client, 0x13A2, nullptr, false);
  REQUIRE(d.ok());
  CHECK(d->spec.type == db::TypeCode::UInt16);
  CHECK_FALSE(d->spec.min);
  CHECK_FALSE(d->spec.max);
  CHECK(d->asked == "type UINT16");
  f.done();
}

TEST_CASE("param_info: LinRS §10.1 the database's type and min kept, only the max asked",
          "[param_info][golden]") {
  test::ManualClient f(956, 958);
  const auto p = known(db::TypeCode::UInt16, 5, std::nullopt);
  auto d = ops::describe_parameter(f.client, 0x13A2, &p, true);
  REQUIRE(d.ok());
  CHECK(d->spec.type == db::TypeCode::UInt16);
  CHECK(d->spec.min == 5);
  CHECK(d->spec.max == 0xFFFF);
  CHECK(d->asked == "max");
  f.done();
}

TEST_CASE("param_info: a parameter the database knows fully costs no telegram", "[param_info]") {
  test::ManualClient f(0, 0);  // no conversation: any request is a mismatch
  const auto p = known(db::TypeCode::SInt16, -100, 100);
  auto d = ops::describe_parameter(f.client, 0x13A2, &p, true);
  REQUIRE(d.ok());
  CHECK(d->spec.min == -100);
  CHECK(d->spec.max == 100);
  CHECK(d->asked.empty());
  f.done();
}

TEST_CASE("param_info: signed limits decoded as the type's integers", "[param_info]") {
  test::SimRig rig("commissioned-axis.json");
  rig.drive->state().put(sim_param(0x13F0, db::TypeCode::SInt16, 0x8000, 0x7FFF));
  rig.drive->state().put(sim_param(0x13F1, db::TypeCode::SInt32, 0x80000000u, 0x7FFFFFFF));
  rig.drive->state().put(sim_param(0x13F2, db::TypeCode::SInt8, 0x80, 0x7F));
  auto s16 = ops::describe_parameter(*rig.client, 0x13F0, nullptr, true);
  REQUIRE(s16.ok());
  CHECK(s16->spec.type == db::TypeCode::SInt16);
  CHECK(s16->spec.min == -32768);
  CHECK(s16->spec.max == 32767);
  CHECK(s16->asked == "type SINT16, min, max");
  auto s32 = ops::describe_parameter(*rig.client, 0x13F1, nullptr, true);
  REQUIRE(s32.ok());
  CHECK(s32->spec.min == -2147483648LL);
  CHECK(s32->spec.max == 2147483647LL);
  auto s8 = ops::describe_parameter(*rig.client, 0x13F2, nullptr, true);
  REQUIRE(s8.ok());
  CHECK(s8->spec.min == -128);
  CHECK(s8->spec.max == 127);
}

TEST_CASE("param_info: a text type has no range to ask, an unknown type code is named by number",
          "[param_info]") {
  test::SimRig rig("commissioned-axis.json");
  rig.drive->state().put(sim_param(0x13F3, db::TypeCode::String, 0, 0));
  sim::Parameter odd = sim_param(0x13F4, db::TypeCode::UInt16, 0, 10);
  odd.type = 0x20;  // a code §10 does not list
  rig.drive->state().put(odd);
  const auto before = rig.drive->stats().telegrams_for_me;
  auto text = ops::describe_parameter(*rig.client, 0x13F3, nullptr, true);
  REQUIRE(text.ok());
  CHECK(text->spec.type == db::TypeCode::String);
  CHECK_FALSE(text->spec.min);
  CHECK(text->asked == "type STRING");
  CHECK(rig.drive->stats().telegrams_for_me == before + 1);
  auto unknown = ops::describe_parameter(*rig.client, 0x13F4, nullptr, true);
  REQUIRE(unknown.ok());
  CHECK_FALSE(unknown->spec.type);
  CHECK_FALSE(unknown->spec.min);
  CHECK_FALSE(unknown->spec.max);
  CHECK(unknown->asked == "type 32");
}

TEST_CASE("param_info: a query the drive refuses leaves that part unknown, a dead link fails",
          "[param_info]") {
  test::SimRig rig("commissioned-axis.json");
  REQUIRE(rig.drive->state().params.count(0x7FF0) == 0);
  auto absent = ops::describe_parameter(*rig.client, 0x7FF0, nullptr, true);
  REQUIRE(absent.ok());
  CHECK_FALSE(absent->spec.type);
  CHECK(absent->asked.empty());
  // The database's type, the drive refusing min and max of a UPID it lacks.
  const auto p = known(db::TypeCode::UInt16, std::nullopt, std::nullopt);
  auto limits = ops::describe_parameter(*rig.client, 0x7FF0, &p, true);
  REQUIRE(limits.ok());
  CHECK(limits->spec.type == db::TypeCode::UInt16);
  CHECK_FALSE(limits->spec.min);
  CHECK_FALSE(limits->spec.max);
  CHECK(limits->asked.empty());

  rig.drive->state().macid = 0x22;  // nobody answers MACID 11h any more
  auto lost = ops::describe_parameter(*rig.client, 0x13A2, nullptr, true);
  REQUIRE_FALSE(lost.ok());
  CHECK(lost.error().code == ErrorClass::link_failure);
}

}  // namespace ops_test_param_info
