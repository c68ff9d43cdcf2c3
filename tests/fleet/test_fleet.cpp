// What a fleet run reports (lib/fleet/fleet.cpp): the commit message and the
// status lines in docs/fleet.md's wording, the counts, the archive path. The
// runs against drives are tested end to end in tests/tools/test_fleet_cli.cpp.
#include <algorithm>
#include <catch2/catch.hpp>
#include <nlohmann/json.hpp>

#include "fleet/fleet.hpp"

// This file's own namespace: the test binary is a unity build (tests/CMakeLists.txt).
namespace fleet_test_fleet {

using namespace lmcfg;
using S = fleet::DriveResult::Status;
using K = ops::DiffItem::Kind;

namespace {

fleet::DriveResult drive(const char* line, const char* name, std::uint8_t id, S status) {
  fleet::DriveResult r;
  r.line = line;
  r.name = name;
  r.id = id;
  r.status = status;
  return r;
}

ops::DiffItem p_gain() {
  ops::DiffItem it;
  it.kind = K::parameter;
  it.layer = 2;
  it.key = 0x13A2;
  it.name = "P Gain Position Controller Set A";
  it.a = "40";
  it.b = "1234";
  return it;
}

// docs/fleet.md's example run: 1 changed, 6 unchanged, 1 failed.
fleet::FleetRun example_run() {
  fleet::FleetRun run;
  auto changed = drive("line1", "press3/x-axis", 0x12, S::changed);
  changed.diff.items.push_back(p_gain());
  run.drives.push_back(changed);
  for (int i = 0; i < 6; ++i)
    run.drives.push_back(drive("line1", "press3/other", std::uint8_t(0x13 + i), S::unchanged));
  auto failed = drive("line2", "press4/x", 0x22, S::failed);
  failed.error = Error(Errc::timeout, "no answer from drive 22h ...");
  run.drives.push_back(failed);
  return run;
}

}  // namespace

TEST_CASE("fleet: the commit message of docs/fleet.md's example run", "[fleet]") {
  const auto run = example_run();
  CHECK(run.count(S::changed) == 1);
  CHECK(run.count(S::unchanged) == 6);
  CHECK(run.count(S::failed) == 1);
  CHECK(fleet::commit_message(run) ==
        "fleet backup: 1 changed, 6 unchanged, 0 new, 1 failed\n"
        "\n"
        "changed press3/x-axis (line line1, MACID 12h): 1 parameter, 0 curves, 0 CT entries\n"
        "  MC 13A2h P Gain Position Controller Set A: 40 -> 1234\n"
        "\n"
        "failed press4/x (line line2, MACID 22h), previous file kept: no answer from drive 22h "
        "...\n");
}

TEST_CASE("fleet: at most 20 differences per drive in a commit message, new drives counted",
          "[fleet]") {
  fleet::FleetRun run;
  auto changed = drive("line1", "press3/x-axis", 0x12, S::changed);
  for (int i = 0; i < 25; ++i) changed.diff.items.push_back(p_gain());
  run.drives.push_back(changed);
  auto added = drive("line1", "press3/z", 0x11, S::added);
  added.parameters = 5;
  added.curves = 1;
  added.ct_entries = 2;
  run.drives.push_back(added);
  auto controller = drive("hall1-can", "press5/controller", 0x05, S::added);
  controller.devicenet = true;
  controller.devicenet_values = 1;
  run.drives.push_back(controller);
  const auto msg = fleet::commit_message(run);
  CHECK(msg.rfind("fleet backup: 1 changed, 0 unchanged, 2 new, 0 failed\n\n"
                  "changed press3/x-axis (line line1, MACID 12h): 25 parameters, 0 curves, 0 CT "
                  "entries\n",
                  0) == 0);
  std::string items;
  for (int i = 0; i < 20; ++i) items += "  MC 13A2h P Gain Position Controller Set A: 40 -> 1234\n";
  CHECK(msg.find(items + "  ... and 5 more\n") != std::string::npos);
  CHECK(msg.find("\nnew press3/z (line line1, MACID 11h): 5 parameters, 1 curve, 2 CT entries\n") !=
        std::string::npos);
  CHECK(msg.find("\nnew press5/controller (line hall1-can, DeviceNet MAC ID 05h): 1 DeviceNet "
                 "value\n") != std::string::npos);
}

TEST_CASE("fleet: differences by kind, each difference as one line", "[fleet]") {
  auto r = drive("hall1-can", "press5/controller", 0x05, S::changed);
  r.devicenet = true;
  ops::DiffItem v;
  v.kind = K::devicenet;
  v.key = 0x24;
  v.name = "Curve Number";
  v.a = "1";
  v.b = "2";
  r.diff.items = {v, v};
  // docs/fleet.md: "drift: press5/controller (line hall1-can, DeviceNet MAC ID
  // 05h): 2 DeviceNet values".
  CHECK(fleet::counts_line(r) == "2 DeviceNet values");
  fleet::FleetRun run;
  run.drives.push_back(r);
  CHECK(fleet::render_text(run, true).rfind(
            "drift: press5/controller (line hall1-can, DeviceNet MAC ID 05h): 2 DeviceNet "
            "values\n",
            0) == 0);
  CHECK(fleet::render_text(run, false).rfind("changed: press5/controller", 0) == 0);

  auto linrs = drive("line1", "press3/x-axis", 0x12, S::changed);
  ops::DiffItem curve;
  curve.kind = K::curve;
  curve.key = 1;
  curve.name = "SinRise";
  curve.a = "70/84 bytes";
  curve.b = "absent";
  ops::DiffItem meta;
  meta.kind = K::metadata;
  meta.name = "firmware";
  meta.a = "3.1";
  meta.b = "3.2";
  ops::DiffItem ct;
  ct.kind = K::ct_entry;
  ct.key = 2;
  ct.a = "present";
  ct.b = "absent";
  ct.detail = "VAI Go To Pos";
  linrs.diff.items = {p_gain(), curve, meta, ct};
  CHECK(fleet::counts_line(linrs) == "1 parameter, 1 curve, 1 CT entry, 1 other difference");
  CHECK(fleet::item_line(curve) == "curve 1 SinRise: 70/84 bytes -> absent");
  CHECK(fleet::item_line(meta) == "metadata firmware: 3.1 -> 3.2");
  CHECK(fleet::item_line(ct) == "CT entry 2: present -> absent (VAI Go To Pos)");
}

TEST_CASE("fleet: status names, the archive path, the summary lines", "[fleet]") {
  CHECK(std::string(fleet::status_name(S::unchanged)) == "unchanged");
  CHECK(std::string(fleet::status_name(S::changed)) == "changed");
  CHECK(std::string(fleet::status_name(S::added)) == "new");
  CHECK(std::string(fleet::status_name(S::failed)) == "failed");
  fleet::DriveEntry d;
  d.name = "press3/x-axis";
  CHECK(fleet::archive_path(d) == "press3/x-axis.json");

  auto run = example_run();
  run.seconds = 1.25;
  const auto backup = fleet::render_text(run, false);
  CHECK(backup.find("failed: press4/x (line line2, MACID 22h): no answer from drive 22h ...\n") !=
        std::string::npos);
  CHECK(backup.find("unchanged:") == std::string::npos);  // counted in the summary only
  CHECK(backup.substr(backup.rfind("8 drive(s)")) ==
        "8 drive(s): 1 changed, 6 unchanged, 0 new, 1 failed; no changes in 1.2 s\n");
  run.drives.push_back(drive("line2", "press4/y", 0x23, S::added));
  run.compared_to = fleet::CommitInfo{"0123456789abcdef0123456789abcdef01234567", "s", "s"};
  const auto status = fleet::render_text(run, true);
  CHECK(status.find("not in archive: press4/y (line line2, MACID 23h)\n") != std::string::npos);
  CHECK(status.substr(status.rfind("9 drive(s)")) ==
        "9 drive(s): 6 as archived, 1 drifted, 1 not in archive, 1 failed (against "
        "0123456789ab) in 1.2 s\n");
  const auto j = nlohmann::json::parse(fleet::render_json(run, true));
  CHECK(j["operation"] == "status");
  CHECK(j["compared_to"] == "0123456789abcdef0123456789abcdef01234567");
  CHECK(j["counts"]["unchanged"] == 6);
  CHECK(j["counts"]["new"] == 1);
  CHECK_FALSE(j.contains("commit"));
  CHECK(j["drives"].size() == 9);
  CHECK(nlohmann::json::parse(fleet::render_json(run, false))["commit"].is_null());
}

}  // namespace fleet_test_fleet

namespace fleet_test_fleet {

TEST_CASE("fleet: what matches means, the rule's settings and status lines with kept values",
          "[fleet][matching]") {
  auto inv = fleet::parse_inventory(
      "[[line]]\nname = \"l1\"\nport = \"/dev/ttyUSB0\"\nbaud = 115200\nignore = [\"0020h\"]\n"
      "[[line.drive]]\nname = \"press3/x\"\nid = 0x12\nignore = [\"1037h\"]\n",
      "plant.toml");
  REQUIRE(inv.ok());
  const auto p = fleet::match_policy(inv->lines[0], inv->lines[0].drives[0]);
  CHECK(p.macid == std::uint8_t{0x12});
  CHECK(p.baud == 115200u);
  CHECK_FALSE(p.include_comm);
  CHECK(std::find(p.ignored.begin(), p.ignored.end(), 0x0020) != p.ignored.end());
  CHECK(std::find(p.ignored.begin(), p.ignored.end(), 0x1037) != p.ignored.end());

  // An ok drive whose kept values are said, not counted as drift.
  fleet::FleetRun run;
  auto r = drive("l1", "press3/x", 0x12, S::unchanged);
  ops::DiffItem baud;
  baud.kind = K::parameter;
  baud.layer = 3;
  baud.key = 0x2012;
  baud.a = "16";
  baud.b = "8";
  r.kept.push_back(ops::KeptValue{baud, ops::KeptBy::communication});
  run.drives.push_back(r);
  run.against_approved = true;
  const std::string text = fleet::render_text(run, true);
  CHECK(text.rfind("kept: press3/x (line l1, MACID 12h): 1 value the drive keeps by policy\n"
                   "    Intf 2012h: approved 16, drive 8 (a communication setting: a restore "
                   "keeps the drive's own value, so that the drive keeps answering on its line "
                   "as it does now)\n"
                   "1 drive(s): 1 as archived, 0 drifted",
                   0) == 0);
  const auto j = nlohmann::json::parse(fleet::render_json(run, true));
  REQUIRE(j["drives"][0]["kept"].size() == 1);
  CHECK(j["drives"][0]["kept"][0]["upid"] == "2012");
  CHECK(j["drives"][0]["kept"][0]["by"] == "communication");
  CHECK(j["counts"]["unchanged"] == 1);
}

}  // namespace fleet_test_fleet
