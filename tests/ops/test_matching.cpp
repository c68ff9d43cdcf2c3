// One meaning of "matches" (lib/ops/matching.cpp, docs/fleet.md "What matches
// means"): the table of values a restore keeps by policy, a diff split by it,
// the exception of a drive whose ROM moves it at its next restart, and the
// texts and JSON a person and a script read.
#include <catch2/catch.hpp>

#include "db/database.hpp"
#include "ops/matching.hpp"
#include "ops/restore.hpp"

// This file's own namespace: the test binary is a unity build (tests/CMakeLists.txt).
namespace ops_test_matching {

using namespace lmcfg;

namespace {

// Recorded as UINT16 (type code 3), as a backup records it.
config::Parameter param(std::uint16_t upid, std::uint32_t value,
                        std::optional<std::uint32_t> def = std::nullopt) {
  return config::Parameter{upid, value, std::uint8_t{3}, def, {}, {}, {}};
}

// A modified-only capture of layers OS and Intf (the LinRS settings are Intf
// UPIDs), no tables, at MACID 12h.
config::DriveConfig capture(std::vector<config::Parameter> os,
                            std::vector<config::Parameter> intf) {
  config::DriveConfig c;
  c.identity.macid = "18";
  c.scope.curves = c.scope.command_table = false;
  c.layer(1) = std::move(os);
  c.layer(3) = std::move(intf);
  return c;
}

ops::MatchPolicy at_12h() {
  ops::MatchPolicy p;
  p.macid = 0x12;
  p.ignored = {0x0020};
  return p;
}

}  // namespace

TEST_CASE("matching: communication parameters are kept by a restore unless it includes them",
          "[matching]") {
  const auto& none = db::Database::empty();
  for (std::uint16_t upid :
       {ops::kBaudRateSource, ops::kBaudRateCode, ops::kMacidSource, ops::kMacidValue}) {
    CHECK(ops::kept_parameter(upid, none, false) == ops::KeptBy::communication);
    CHECK_FALSE(ops::kept_parameter(upid, none, true));
  }
  CHECK_FALSE(ops::kept_parameter(0x0010, none, false));
  ops::DiffItem macid;
  macid.kind = ops::DiffItem::Kind::metadata;
  macid.name = "macid";
  CHECK(ops::kept_by(macid, none, {}) == ops::KeptBy::unit);
  macid.name = "firmware";
  CHECK_FALSE(ops::kept_by(macid, none, {}));
}

TEST_CASE("matching: a used spare's other communication settings are kept, its other values differ",
          "[matching]") {
  const auto& none = db::Database::empty();
  // Approved: baud and MACID by parameter (LinRS §10.2), OS 0010h = 5.
  const auto approved = capture(
      {param(0x0010, 5, 0), param(0x0020, 1000, 1000)},
      {param(0x200E, 2, 1), param(0x2012, 16, 16), param(0x206C, 3, 1), param(0x2076, 0x12, 17)});
  // The spare: its switches choose baud rate and MACID, 2012h holds another
  // code, OS 0010h = 7, the ignored 0020h another live value.
  const auto spare = capture({param(0x0010, 7, 0), param(0x0020, 4, 1000)},
                             {param(0x2012, 8, 16), param(0x2076, 0x12, 17)});
  const auto d = ops::diff(approved, spare, none, nullptr, {});
  const auto m = ops::match(d, spare, none, at_12h());
  REQUIRE(m.differences.size() == 1);
  CHECK(m.differences[0].key == 0x0010);
  CHECK_FALSE(m.matches());
  REQUIRE(m.kept.size() == 3);
  CHECK(m.kept[0].item.key == 0x200E);
  CHECK(m.kept[1].item.key == 0x2012);
  CHECK(m.kept[2].item.key == 0x206C);
  CHECK(ops::kept_text(m.kept[1]) == "Intf 2012h: approved 16, drive 8");
  CHECK(ops::kept_text(m.kept[1], "file") == "Intf 2012h: file 16, drive 8");
  const auto j = ops::kept_json(m.kept[1]);
  CHECK(j["kind"] == "parameter");
  CHECK(j["layer"] == "Intf");
  CHECK(j["upid"] == "2012");
  CHECK(j["configuration"] == "16");
  CHECK(j["drive"] == "8");
  CHECK(j["by"] == "communication");
  CHECK(j["reason"] ==
        "a communication setting: a restore keeps the drive's own value, so that the drive keeps "
        "answering on its line as it does now");
  CHECK(j["text"] == "Intf 2012h: approved 16, drive 8");

  // The same drive with OS 0010h restored: it matches, three values kept.
  auto restored = spare;
  restored.layer(1)[0].value = 5;
  const auto after =
      ops::match(ops::diff(approved, restored, none, nullptr, {}), restored, none, at_12h());
  CHECK(after.matches());
  CHECK(after.kept.size() == 3);

  // With the communication parameters included they are differences.
  auto p = at_12h();
  p.include_comm = true;
  const auto with_comm =
      ops::match(ops::diff(approved, restored, none, nullptr, {}), restored, none, p);
  CHECK(with_comm.differences.size() == 3);
  CHECK(with_comm.kept.empty());
}

TEST_CASE("matching: kept settings that move the drive at its next restart are differences",
          "[matching]") {
  const auto& none = db::Database::empty();
  const auto approved = capture({}, {param(0x206C, 3, 1), param(0x2076, 0x12, 17)});
  // LinRS §15: MACID By Parameter, 2076h = 11h, written without a restart:
  // the drive answers at 12h now and at 11h after the next power cycle.
  const auto moving = capture({}, {param(0x206C, 3, 1), param(0x2076, 0x11, 17)});
  CHECK(ops::moves_at_restart(moving, none, at_12h())
            .rfind("after its next restart the drive answers at MACID 11h, not at 12h where the "
                   "inventory has it (",
                   0) == 0);
  const auto m = ops::match(ops::diff(approved, moving, none, nullptr, {}), moving, none, at_12h());
  CHECK(m.kept.empty());
  REQUIRE(m.differences.size() == 2);
  CHECK(m.differences[0].key == 0x2076);
  CHECK(m.differences[1].name == "link after restart");
  CHECK(m.differences[1].a == "MACID 12h");
  // Where the inventory names no MACID (or the ROM keeps it), nothing moves.
  CHECK(ops::moves_at_restart(moving, none, {}).empty());
  CHECK(ops::moves_at_restart(approved, none, at_12h()).empty());
}

}  // namespace ops_test_matching
