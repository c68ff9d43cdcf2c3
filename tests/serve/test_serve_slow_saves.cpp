// lmcfg serve's automatic restore (on_replaced = "restore") onto a drive whose
// saves take 40 s, answered late or never (docs/field.md "Slow saves";
// field reports: "A command table flash save took about 39 s and was
// never acknowledged"). The service runs ops::run_restore: the same rule as
// the tool, so the restore succeeds under both readings.
#include <catch2/catch.hpp>
#include <nlohmann/json.hpp>

#include "files.hpp"
#include "serve_rig.hpp"

// This file's own namespace: the test binary is a unity build (tests/CMakeLists.txt).
namespace serve_test_serve_slow_saves {

using namespace lmcfg;
using namespace lmcfg::test;
using namespace std::chrono_literals;

namespace {

// The factory-fresh axis of serve_rig.hpp, whose flash saves and defaulting
// take 40 s: answered then, or never (the simulator's unanswered_saves).
void write_slow_fresh_axis(const fs::path& path, int id, bool answered) {
  write_fresh_axis(path, id);
  auto j = nlohmann::json::parse(slurp(path));
  j["timing_us"]["flash_save"] = 40'000'000;
  j["timing_us"]["defaulting"] = 40'000'000;
  j["options"]["unanswered_saves"] = !answered;
  spit(path, j.dump(1));
}

}  // namespace

TEST_CASE("field reports: serve: the automatic restore onto a drive with 40 s saves",
          "[serve][replaced][slow_saves]") {
  for (const bool answered : {true, false}) {
    DYNAMIC_SECTION((answered ? "answered late" : "never answered")) {
      Rig rig("", "on_replaced = \"restore\"\n");
      const auto t0 = rig.now;
      rig.at(t0);
      write_slow_fresh_axis(rig.dir.path / "a.json", 0x11, answered);
      rig.at(t0 + 15min);
      auto events = rig.take_events();
      INFO(nlohmann::json(events).dump());
      REQUIRE(events.size() == 2);
      CHECK(events[0]["event"] == "replaced");
      CHECK(events[1]["event"] == "restored");
      CHECK(events[1]["automatic"] == true);
      CHECK(events[1]["outcome"] == "restored and verified");
      CHECK((*rig.service->drive("press3/z"))["status"] == "ok");
      // The saves reached flash: the drive's state file holds the tables.
      const auto state = nlohmann::json::parse(slurp(rig.dir.path / "a.json"));
      CHECK_FALSE(state["command_table"]["flash"].empty());
      CHECK_FALSE(state["curves"]["flash"].empty());
    }
  }
}

}  // namespace serve_test_serve_slow_saves
