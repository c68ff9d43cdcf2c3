// lmcfg ui in headless Chromium (tests/browser/walk-console.js over the
// DevTools protocol) against simulated drives, as a technician: open the
// printed address, find the practice drive (the demo axis), back it up, compare it with
// factory defaults, find a used spare, restore the backup onto it through
// the plan page, compare again (identical), undo. Screenshots at 1280 and
// 390 px are kept in build/tests/console-shots/ui-*.png.
#include <catch2/catch.hpp>
#include <map>
#include <nlohmann/json.hpp>

#include "console_walk.hpp"
#include "ui_rig.hpp"

namespace ui_test_ui_browser {

using namespace lmcfg;
using json = nlohmann::json;
namespace fs = std::filesystem;

std::string fixture_port(const test::UiRig& rig, const char* name) {
  const fs::path to = rig.dir() / name;
  fs::copy_file(fs::path(LMCFG_SOURCE_DIR) / "tests/fixtures/sim" / name, to,
                fs::copy_options::overwrite_existing);
  return "sim:" + to.string();
}

std::string key_of(const std::string& port) {
  ui::DriveLink l;
  l.port = port;
  l.id = 0x11;
  return ui::drive_key(l);
}

TEST_CASE("ui in Chromium: find, back up, compare, restore onto a used spare, undo",
          "[ui_browser][browser]") {
  // The practice drive is the README demo axis, as lmcfg ui offers it.
  test::UiRig rig(
      "ui-browser", db::Database::empty(),
      test::slurp(fs::path(LMCFG_SOURCE_DIR) / "tests/fixtures/sim/commissioned-axis.json"));
  rig.serve_in_background();
  const std::string original = rig.desk().practice_port();
  const std::string spare = fixture_port(rig, "used-spare.json");
  const std::string base = rig.base();
  const std::string drive_a = base + "/drive?key=" + test::form_encode(key_of(original));
  const std::string drive_b = base + "/drive?key=" + test::form_encode(key_of(spare));
  json steps = json::array();
  std::map<std::string, std::size_t> named;
  auto step = [&](json st, const std::string& name = "") {
    if (!name.empty()) named[name] = steps.size();
    steps.push_back(std::move(st));
  };
  auto read = [&](const std::string& name) { step({{"op", "read"}}, name); };
  auto shot = [&](const std::string& name) { step(test::console_shot("ui-" + name)); };
  auto narrow = [&](const std::string& name) {
    step({{"op", "viewport"}, {"width", 390}, {"height", 844}});
    read(name + "-390");
    shot(name + "-390.png");
    step({{"op", "viewport"}, {"width", 1280}, {"height", 900}});
  };
  auto done = [&](const std::string& name) {
    step({{"op", "wait"}, {"selector", ".job-state[data-state=done]"}, {"timeout_ms", 60000}},
         name);
  };
  auto find = [&](const std::string& port, const std::string& name) {
    step({{"op", "goto"}, {"url", base + "/"}});
    step({{"op", "fill"}, {"selector", "#port"}, {"value", port}});
    step({{"op", "fill"}, {"selector", "#baud"}, {"value", "57600"}});
    step({{"op", "fill"}, {"selector", "#from"}, {"value", "16"}});
    step({{"op", "fill"}, {"selector", "#to"}, {"value", "18"}});
    step({{"op", "submit"}, {"selector", "#find-form button[type=submit]"}});
    done(name);
  };
  step({{"op", "goto"}, {"url", base + "/?token=T0KEN"}});
  read("connect");
  shot("connect-1280.png");
  narrow("connect");
  step({{"op", "submit"}, {"selector", "#practice button"}});  // "Find the practice drive"
  done("found-a");
  read("found");
  step({{"op", "goto"}, {"url", base + "/"}});  // the drive found, on the connect page
  narrow("connect-found");
  step({{"op", "goto"}, {"url", drive_a}});
  read("drive-a");
  shot("drive-1280.png");
  narrow("drive");
  step({{"op", "submit"}, {"selector", "#backup"}});
  done("backup-done");
  read("backup");
  shot("backup-done-1280.png");
  step({{"op", "goto"}, {"url", drive_a}});
  step({{"op", "fill"}, {"selector", "#against"}, {"value", "defaults"}});
  step({{"op", "submit"}, {"selector", "#compare"}});
  done("compare-done");
  read("compare");
  step({{"op", "submit"}, {"selector", "#diff-page"}});
  shot("compare-defaults-1280.png");
  find(spare, "found-b");
  step({{"op", "goto"}, {"url", drive_b}});
  step({{"op", "eval"}, {"expression", "document.querySelector('#file option').value"}}, "file");
  step({{"op", "submit"}, {"selector", "#plan"}});
  done("plan-done");
  step({{"op", "submit"}, {"selector", "#plan-page"}});
  read("plan");
  shot("plan-1280.png");
  narrow("plan");
  step({{"op", "eval"},
        {"expression",
         "(() => { const b = document.querySelector('#skip-incompatible'); if (b) b.checked = "
         "true; return b !== null; })()"}},
       "incompatible");
  step({{"op", "fill"}, {"selector", "#reason"}, {"value", "spare for axis 1 <b>&amp;</b>"}});
  step({{"op", "submit"}, {"selector", "#execute"}});
  done("restore-done");
  read("restored");
  shot("restore-done-1280.png");
  narrow("restore-done");
  step({{"op", "goto"}, {"url", drive_b}});
  step({{"op", "eval"},  // the file restored: the first after "factory defaults"
        {"expression", "document.querySelector('#against').selectedIndex = 1"}});
  step({{"op", "submit"}, {"selector", "#compare"}});
  done("same-done");
  read("same");
  step({{"op", "goto"}, {"url", drive_b}});
  read("journal");
  shot("drive-journal-1280.png");
  step({{"op", "submit"}, {"selector", "#undo"}});
  done("undo-plan-done");
  step({{"op", "submit"}, {"selector", "#plan-page"}});
  read("undo-plan");
  step({{"op", "fill"}, {"selector", "#reason"}, {"value", "back as it was"}});
  step({{"op", "submit"}, {"selector", "#execute"}});
  done("undo-done");
  read("undone");
  const json w = test::console_walk(rig.dir(), steps);
  if (w.is_null()) return;
  const auto& s = w["steps"];
  REQUIRE(s.size() == steps.size());
  CHECK(w["console_errors"] == json::array());
  CHECK(w["requests"] == json::array());
  CHECK(w["dialogs"] == json::array());
  auto at = [&](const std::string& name) -> const json& { return s[named.at(name)]; };
  auto has = [&](const std::string& name, const std::string& needle) {
    INFO("step " << name << ": " << needle);
    return at(name)["value"]["text"].get<std::string>().find(needle) != std::string::npos;
  };
  CHECK(at("connect")["url"] == base + "/");  // the token left the address
  CHECK(at("connect")["value"]["h1"] == "Connect a drive");
  CHECK(at("connect")["value"]["scripts"] == 0);
  for (const char* n :
       {"connect-390", "connect-found-390", "drive-390", "plan-390", "restore-done-390"}) {
    INFO(n);
    CHECK(at(n)["value"]["width"].get<int>() <= 390);  // no sideways scrolling
  }
  CHECK(at("found-a")["value"] == true);
  CHECK(has("found", "Found 1 drive(s)."));
  CHECK(has("drive-a", "Operation Enabled"));
  CHECK(at("backup-done")["value"] == true);
  CHECK(has("backup", "Backed up into"));
  CHECK(has("compare", "The drive differs in"));
  CHECK(at("found-b")["value"] == true);
  CHECK(at("file")["value"].get<std::string>().rfind(key_of(original) + "-", 0) == 0);
  CHECK(has("plan", "What will be written"));
  CHECK(has("plan", "not factory-fresh"));
  CHECK(at("restore-done")["value"] == true);
  CHECK(has("restored", "Restored"));
  CHECK(at("same-done")["value"] == true);
  CHECK(has("same", "Identical: the drive holds what it is compared with."));
  CHECK(has("journal", "spare for axis 1 <b>&amp;</b>"));
  CHECK(at("undo-done")["value"] == true);
  CHECK(has("undone", "Restored and verified"));
}

}  // namespace ui_test_ui_browser
