// What the restore phases share (lib/ops/restore.cpp): which UPIDs are
// communication parameters, the labels of parameters in plans and problems,
// and a curve's name from its info block. Tagged [ops_restore]: [restore]
// runs every restore test.
#include <catch2/catch.hpp>

#include "db_test_support.hpp"
#include "ops/restore.hpp"
#include "ops/restore_internal.hpp"

// This file's own namespace: the test binary is a unity build (tests/CMakeLists.txt).
namespace ops_test_restore {

using namespace lmcfg;

// LinRS §10.2: "In the following example the changed parameters of the Intf SW
// (LinRS) ... UPID: 0x200Eh, Baud Rate Source Select ... UPID: 0x2012h, Baud
// Rate Parameter Def ... UPID: 0x206Ch, MACID Source Select ... UPID: 0x2076h,
// MACID Parameter Value".
TEST_CASE(
    "LinRS §10.2 restore: the four LinRS settings are communication parameters without a "
    "database",
    "[ops_restore]") {
  const auto& none = db::Database::empty();
  for (std::uint16_t upid :
       {ops::kBaudRateSource, ops::kBaudRateCode, ops::kMacidSource, ops::kMacidValue}) {
    INFO("UPID " << upid);
    CHECK(ops::is_comm_parameter(none, upid));
  }
  CHECK_FALSE(ops::is_comm_parameter(none, 0x2008));
  CHECK_FALSE(ops::is_comm_parameter(none, 0x13A2));
  CHECK_FALSE(ops::is_comm_parameter(none, 0x0000));
  CHECK_FALSE(ops::is_comm_parameter(none, 0xFFFF));
  CHECK(ops::kBaudRateByParameter == 2);  // §10.2: "Value: 0x00000002h, By Parameter"
  CHECK(ops::kMacidByParameter == 3);     // §10.2: "Value: 0x00000003h, By Parameter"
}

TEST_CASE("restore: the database's comm flag makes a parameter a communication parameter",
          "[ops_restore]") {
  const auto& fixture = db::test::fixture_db();
  CHECK(ops::is_comm_parameter(fixture, 0x2008));        // comm = 1 in the fixture
  CHECK_FALSE(ops::is_comm_parameter(fixture, 0x2200));  // an Intf UPID without the flag
  CHECK_FALSE(ops::is_comm_parameter(fixture, 0x13A2));
  CHECK(ops::is_comm_parameter(fixture, 0x2076));  // not in the fixture: still one
}

TEST_CASE("restore: a parameter's label is layer, UPID and the database's name, else the file's",
          "[ops_restore]") {
  using ops::detail::param_label;
  using ops::detail::param_name;
  const auto& fixture = db::test::fixture_db();
  const db::Parameter* gain = fixture.find(0x13A2);
  REQUIRE(gain != nullptr);
  config::Parameter from_file{0x13A2, 40, std::nullopt, std::nullopt, {}, {}, {}};
  from_file.name = "Gain in the file";
  CHECK(param_label(2, 0x13A2, gain, &from_file) == "MC 13A2h P Gain Position Controller Set A");
  CHECK(param_label(2, 0x13A2, nullptr, &from_file) == "MC 13A2h Gain in the file");
  CHECK(param_label(2, 0x13A2, nullptr, nullptr) == "MC 13A2h");
  CHECK(param_label(1, 0x0010, nullptr, nullptr) == "OS 0010h");
  CHECK(param_label(3, 0x2076, nullptr, nullptr) == "Intf 2076h");
  CHECK(param_label(4, 0x3001, fixture.find(0x3001), nullptr) == "Appl 3001h Enable Feature");
  CHECK(param_name(0x13A2, nullptr, &from_file) == "Gain in the file");
  CHECK(param_name(0x13A2, gain, nullptr) == "P Gain Position Controller Set A");
  CHECK(param_name(0x13A2, nullptr, nullptr).empty());
}

// LinRS §11.1 "Reading Curve 1 Info Block Data": the info block's first 16
// bytes as the captured answers carry them (46 00 03 00, 15 00 04 00,
// 53 69 6E 52, 69 73 65 00), then zeros.
TEST_CASE("LinRS §11.1 restore: a curve's name is the info block's text from offset 8",
          "[ops_restore]") {
  using ops::detail::curve_name;
  Bytes info = *from_hex("46 00 03 00 15 00 04 00 53 69 6E 52 69 73 65 00");
  info.resize(0x46, 0x00);
  CHECK(curve_name(info) == "SinRise");
  // Shorter blocks: what there is; none at all below offset 8.
  CHECK(curve_name(Bytes(info.begin(), info.begin() + 12)) == "SinR");
  CHECK(curve_name(Bytes(info.begin(), info.begin() + 8)).empty());
  CHECK(curve_name(Bytes{}).empty());
  // At most 22 characters (offsets 8..29), without a terminating zero.
  Bytes full(40, 'A');
  CHECK(curve_name(full) == std::string(22, 'A'));
}

}  // namespace ops_test_restore
