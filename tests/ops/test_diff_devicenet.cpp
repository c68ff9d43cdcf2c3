// diff of DeviceNet captures (seed 000): values per motor and Get command ID,
// live values only when asked, the section's metadata, and a DeviceNet capture
// against a LinRS capture or the factory defaults.
#include <unistd.h>

#include <catch2/catch.hpp>
#include <cstdlib>
#include <filesystem>

#include "config/config_io.hpp"
#include "db/database.hpp"
#include "ops/diff.hpp"
#include "report/report.hpp"
#include "subprocess.hpp"
#include "test_config_support.hpp"

// This file's own namespace: the test binary is a unity build (tests/CMakeLists.txt).
namespace ops_test_diff_devicenet {

using namespace lmcfg;
using namespace lmcfg::config;
using namespace lmcfg::config::testing;
namespace fs = std::filesystem;

namespace {

const db::Database& real_db() {
  static auto db = db::Database::open(LMCFG_DB_PATH);
  REQUIRE(db.ok());
  return *db;
}

DevicenetValue& value_of(DriveConfig& c, int motor, std::uint8_t command) {
  for (auto& v : c.devicenet->values)
    if (v.motor == motor && v.command == command) return v;
  FAIL("no such value");
  throw;
}

// devicenet_capture() with two values changed: motor A's Controller P and
// motor B's curve number.
DriveConfig changed() {
  auto b = devicenet_capture();
  value_of(b, 0, 0x34).raw = 1100;
  value_of(b, 0, 0x34).scaled = "2.57818";
  value_of(b, 1, 0x24).raw = 5;
  return b;
}

}  // namespace

TEST_CASE("diff: two identical DeviceNet captures are identical", "[diff][devicenet]") {
  const auto a = devicenet_capture();
  ops::DiffOptions opt;
  opt.include_live = true;
  const auto r = ops::diff(a, a, real_db(), {}, opt);
  CHECK(r.identical());
  CHECK(r.notes.empty());
  CHECK(ops::render_text(r, "a.json", "b.json") ==
        "--- a.json (DeviceNet controller values and live values)\n"
        "+++ b.json (DeviceNet controller values and live values)\n"
        "\n"
        "identical\n");
}

TEST_CASE("diff: DeviceNet values that differ, as text and JSON", "[diff][devicenet]") {
  const auto r = ops::diff(devicenet_capture(), changed(), real_db(), {}, {});
  REQUIRE(r.items.size() == 2);
  CHECK(r.items[0].kind == ops::DiffItem::Kind::devicenet);
  CHECK(r.items[0].motor == 0);
  CHECK(r.items[0].key == 0x34);
  CHECK(r.items[1].motor == 1);
  CHECK(r.items[1].key == 0x24);
  CHECK(std::string(ops::kind_name(r.items[0].kind)) == "devicenet");
  CHECK(ops::render_text(r, "a.json", "b.json") ==
        "--- a.json (DeviceNet controller values)\n"
        "+++ b.json (DeviceNet controller values)\n"
        "\n"
        "devicenet:\n"
        "  motor A: Controller P (34h): 2.3438 A/mm (raw 1000) -> 2.57818 A/mm (raw 1100)\n"
        "  motor B: (Rise) Curve Number (24h): 3 -> 5\n"
        "\n"
        "2 difference(s)\n");
  CHECK(ops::render_json(r, "a.json", "b.json") ==
        R"json({
  "a": "a.json",
  "b": "b.json",
  "identical": false,
  "scope": {
    "a": {
      "layers": [],
      "parameters": "modified",
      "curves": false,
      "command_table": false
    },
    "b": {
      "layers": [],
      "parameters": "modified",
      "curves": false,
      "command_table": false
    },
    "compared": {
      "layers": [],
      "parameters": "modified",
      "curves": false,
      "command_table": false
    }
  },
  "devicenet": {
    "a": true,
    "b": true,
    "live": false
  },
  "differences": [
    {
      "kind": "devicenet",
      "motor": "A",
      "command": "34",
      "name": "motor A: Controller P (34h)",
      "a": "2.3438 A/mm (raw 1000)",
      "b": "2.57818 A/mm (raw 1100)"
    },
    {
      "kind": "devicenet",
      "motor": "B",
      "command": "24",
      "name": "motor B: (Rise) Curve Number (24h)",
      "a": "3",
      "b": "5"
    }
  ],
  "notes": []
}
)json");
}

TEST_CASE("diff: DeviceNet signed words, names and scales without the database",
          "[diff][devicenet]") {
  auto a = devicenet_capture();
  auto b = devicenet_capture();
  value_of(b, 0, 0x40).raw = 0xFC00;  // -1024: -20 mm
  const auto r = ops::diff(a, b, real_db(), {}, {});
  REQUIRE(r.items.size() == 1);
  CHECK(r.items[0].name == "motor A: Minimal Position (40h)");
  CHECK(r.items[0].a == "-10 mm (raw 65024)");
  CHECK(r.items[0].b == "-20 mm (raw 64512)");
  // Without the database: the capture's name and scaled text, else the command ID.
  auto c = changed();
  value_of(c, 1, 0x24).name.clear();
  const auto e = ops::diff(devicenet_capture(), c, db::Database::empty(), {}, {});
  REQUIRE(e.items.size() == 2);
  CHECK(e.items[0].name == "motor A: Controller P (34h)");
  CHECK(e.items[0].a == "2.3438 A/mm (raw 1000)");
  CHECK(e.items[0].b == "2.57818 A/mm (raw 1100)");
  CHECK(e.items[1].name == "motor B: (Rise) Curve Number (24h)");  // A's name
  auto d = devicenet_capture();
  value_of(d, 1, 0x24).name.clear();
  const auto n = ops::diff(d, c, db::Database::empty(), {}, {});
  REQUIRE(n.items.size() == 2);
  CHECK(n.items[1].name == "motor B: command 24h");
  CHECK(n.items[1].a == "3");
  // A value on one side only.
  auto one = devicenet_capture();
  one.devicenet->values.pop_back();
  const auto o = ops::diff(devicenet_capture(), one, real_db(), {}, {});
  REQUIRE(o.items.size() == 1);
  CHECK(o.items[0].b == "absent");
}

TEST_CASE("diff: DeviceNet live values are compared only when asked", "[diff][devicenet]") {
  auto b = devicenet_capture();
  b.devicenet->live[0].raw = 7;  // the controller's status low word
  CHECK(ops::diff(devicenet_capture(), b, real_db(), {}, {}).identical());
  ops::DiffOptions opt;
  opt.include_live = true;
  const auto r = ops::diff(devicenet_capture(), b, real_db(), {}, opt);
  REQUIRE(r.items.size() == 1);
  CHECK(r.items[0].live);
  CHECK(r.live_compared);
  CHECK(ops::render_text(r, "a", "b") ==
        "--- a (DeviceNet controller values and live values)\n"
        "+++ b (DeviceNet controller values and live values)\n"
        "\n"
        "devicenet live:\n"
        "  controller: Status Low Word (02h): 3 -> 7\n"
        "\n"
        "1 difference(s)\n");
  CHECK(ops::render_json(r, "a", "b").find("\"command\": \"02\",\n      \"live\": true,") !=
        std::string::npos);
}

TEST_CASE("diff: DeviceNet bit rate, IO modules and motors are metadata", "[diff][devicenet]") {
  auto b = devicenet_capture();
  b.identity.macid = "7";
  b.devicenet->can_bitrate = 500000;
  b.devicenet->io_modules.pop_back();
  const auto r = ops::diff(devicenet_capture(), b, real_db(), {}, {});
  CHECK(ops::render_text(r, "a", "b") ==
        "--- a (DeviceNet controller values)\n"
        "+++ b (DeviceNet controller values)\n"
        "\n"
        "identity:\n"
        "  macid: 5 -> 7\n"
        "  devicenet can_bitrate: 125000 -> 500000\n"
        "  devicenet io_modules: control-in, addressed-in, status-out, addressed-out -> "
        "control-in, addressed-in, status-out\n"
        "\n"
        "3 difference(s)\n");
  // The MAC ID and the bit rate are the unit's own.
  ops::DiffOptions unit;
  unit.ignore_unit = true;
  const auto u = ops::diff(devicenet_capture(), b, real_db(), {}, unit);
  REQUIRE(u.items.size() == 1);
  CHECK(u.items[0].name == "devicenet io_modules");
  ops::DiffOptions meta;
  meta.ignore_metadata = true;
  CHECK(ops::diff(devicenet_capture(), b, real_db(), {}, meta).identical());
  // Motor B removed: its values are on one side only.
  auto m = devicenet_capture();
  m.devicenet->motors = {0};
  std::erase_if(m.devicenet->values, [](const DevicenetValue& v) { return v.motor == 1; });
  const auto mr = ops::diff(devicenet_capture(), m, real_db(), {}, {});
  REQUIRE(mr.items.size() == 3);
  CHECK(mr.items[0].name == "devicenet motors");
  CHECK(mr.items[0].a == "A, B");
  CHECK(mr.items[0].b == "A");
  CHECK(mr.items[1].b == "absent");
}

TEST_CASE("diff: a DeviceNet capture against a LinRS capture is not comparable",
          "[diff][devicenet]") {
  const auto r = ops::diff(devicenet_capture(), golden_sinrise(), real_db(), {}, {});
  REQUIRE(r.items.size() == 1);
  CHECK(r.items[0].kind == ops::DiffItem::Kind::scope);
  CHECK(ops::render_text(r, "dn.json", "rs.json") ==
        "--- dn.json (DeviceNet controller values)\n"
        "+++ rs.json (modified parameters of OS, MC, Intf, Appl; curves; command table)\n"
        "\n"
        "scope:\n"
        "  controller: DeviceNet controller -> LinRS drive (not comparable)\n"
        "note: A is a DeviceNet controller capture, B a LinRS drive capture: not comparable\n"
        "\n"
        "1 difference(s)\n");
  const auto back = ops::diff(golden_sinrise(), devicenet_capture(), real_db(), {}, {});
  REQUIRE(back.notes.size() == 1);
  CHECK(back.notes[0] ==
        "A is a LinRS drive capture, B a DeviceNet controller capture: not comparable");
}

TEST_CASE("diff: a DeviceNet capture has no factory defaults to compare with",
          "[diff][devicenet]") {
  const auto dn = devicenet_capture();
  ops::DiffOptions opt;
  opt.a_is_defaults = true;
  const auto r = ops::diff(ops::factory_defaults_config(dn.scope), dn, real_db(), {}, opt);
  CHECK(ops::render_text(r, "defaults", "dn.json") ==
        "--- defaults (modified parameters of no layer; no curves; no command table)\n"
        "+++ dn.json (DeviceNet controller values)\n"
        "\n"
        "scope:\n"
        "  devicenet values: no factory defaults -> captured (4 value(s) on the B side not "
        "compared)\n"
        "note: B is a DeviceNet controller capture: lmcfg knows no factory defaults of its "
        "values, so there is nothing to compare it with\n"
        "\n"
        "1 difference(s)\n");
}

TEST_CASE("lmcfg diff: DeviceNet files, --live, defaults and LinRS", "[diff][devicenet][cli]") {
  test::ScratchDir d("diffdn");
  const auto a = d.path / "a.json", b = d.path / "b.xml", c = d.path / "c.json";
  REQUIRE(write_config_file(devicenet_capture(), a).ok());
  REQUIRE(write_config_file(changed(), b).ok());
  auto live = devicenet_capture();
  live.devicenet->live[1].raw = 600;
  REQUIRE(write_config_file(live, c).ok());
  const std::string fa = "'" + a.string() + "'", fb = "'" + b.string() + "'",
                    fc = "'" + c.string() + "'";
  auto same = test::run_tool_in(d.path, "diff --quiet " + fa + " " + fa);
  CHECK(same.exit_code == 0);
  CHECK(same.out.find("\nidentical\n") != std::string::npos);
  auto two = test::run_tool_in(d.path, "diff --quiet " + fa + " " + fb);
  CHECK(two.exit_code == 1);
  CHECK(two.out.find("  motor A: Controller P (34h): 2.3438 A/mm (raw 1000) -> 2.57818 A/mm "
                     "(raw 1100)\n") != std::string::npos);
  CHECK(test::run_tool_in(d.path, "diff --quiet " + fa + " " + fc).exit_code == 0);
  auto with_live = test::run_tool_in(d.path, "diff --quiet --live " + fa + " " + fc);
  CHECK(with_live.exit_code == 1);
  CHECK(with_live.out.find("devicenet live:\n  motor A: Actual Position (18h): 10 mm (raw 512) "
                           "-> 11.71875 mm (raw 600)\n") != std::string::npos);
  auto defaults = test::run_tool_in(d.path, "diff --quiet defaults " + fa);
  CHECK(defaults.exit_code == 1);
  CHECK(defaults.out.find("note: B is a DeviceNet controller capture: lmcfg knows no factory "
                          "defaults of its values, so there is nothing to compare it with\n") !=
        std::string::npos);
  const auto rs = (fixture_dir() / "golden-sinrise.json").string();
  auto linrs = test::run_tool_in(d.path, "diff --quiet " + fa + " '" + rs + "' --json");
  CHECK(linrs.exit_code == 1);
  CHECK(linrs.out.find("\"A is a DeviceNet controller capture, B a LinRS drive capture: not "
                       "comparable\"") != std::string::npos);
  // convert is lossless for the section.
  const auto x = d.path / "a.xml", j = d.path / "back.json";
  REQUIRE(test::run_tool_in(d.path, "convert --quiet " + fa + " '" + x.string() + "'").exit_code ==
          0);
  REQUIRE(test::run_tool_in(d.path, "convert --quiet '" + x.string() + "' '" + j.string() + "'")
              .exit_code == 0);
  CHECK(slurp(j) == slurp(a));
  CHECK(*read_config_file(x) == devicenet_capture());
}

TEST_CASE("report: a DeviceNet capture's values, alone and against another",
          "[report][devicenet]") {
  const auto one = report::render_report(devicenet_capture(), "dn.json", real_db(), {});
  CHECK(one.find("<section class=\"page\" id=\"devicenet\"><h2>DeviceNet values</h2>") !=
        std::string::npos);
  CHECK(one.find("<a href=\"#command-table\">Command table</a><a href=\"#devicenet\">DeviceNet "
                 "values</a></nav>") != std::string::npos);
  CHECK(one.find("<tr><th>motors</th><td>A, B</td></tr>") != std::string::npos);
  CHECK(one.find("<tr><td>motor A: Controller P (34h)</td><td>2.3438 A/mm (raw 1000)</td><td>"
                 "</td></tr>") != std::string::npos);
  CHECK(one.find("<tr><td>controller: Status Low Word (02h)</td><td>3</td><td>live (not "
                 "restored)</td></tr>") != std::string::npos);
  CHECK(report::render_report(golden_sinrise(), "rs.json", real_db(), {}).find("DeviceNet") ==
        std::string::npos);
  const auto a = devicenet_capture();
  const auto b = changed();
  const auto r = ops::diff(a, b, real_db(), {}, {});
  const auto two = report::render_diff_report(a, "a.json", b, "b.json", r, real_db(), {});
  CHECK(two.find("<a href=\"#devicenet\">DeviceNet values</a></nav>") != std::string::npos);
  CHECK(two.find("<tr data-summary=\"devicenet\"><td>DeviceNet values</td><td class=\"num\">2"
                 "</td>") != std::string::npos);
  CHECK(two.find("<tr class=\"diff changed\" data-kind=\"devicenet\" data-key=\"A/34\"><td>motor "
                 "A: Controller P (34h)</td>") != std::string::npos);
}

}  // namespace ops_test_diff_devicenet
