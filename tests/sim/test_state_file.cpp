// The sim state file (lib/sim/state_file.cpp, docs/simulator.md): JSON round
// trips, the fixtures, loading a line of drives, and the messages for files
// it refuses.
#include <cstdio>
#include <filesystem>
#include <set>

#include "files.hpp"
#include "test_sim_harness.hpp"

// This file's own namespace: the test binary is a unity build (tests/CMakeLists.txt).
namespace sim_test_state_file {

using namespace lmcfg;
using namespace lmcfg::codec;
using lmcfg::test::load_fixture;
using lmcfg::test::SimHarness;

namespace {
constexpr std::uint8_t kId = 0x11;

std::string fixture_path(const char* name) {
  return std::string(LMCFG_SOURCE_DIR) + "/tests/fixtures/sim/" + name;
}
}  // namespace

TEST_CASE("sim: state file round trip and fixtures", "[sim]") {
  for (const char* name : {"commissioned-axis.json", "used-spare.json", "manual-drive.json"}) {
    INFO(name);
    auto s = load_fixture(name);
    auto again = sim::from_json(sim::to_json(s));
    REQUIRE(again.ok());
    CHECK(again->params == s.params);
    CHECK(again->curves_ram == s.curves_ram);
    CHECK(again->curves_flash == s.curves_flash);
    CHECK(again->ct_ram == s.ct_ram);
    CHECK(again->ct_flash == s.ct_flash);
    CHECK(again->macid == s.macid);
    CHECK(again->link == s.link);
    CHECK(again->checksum == s.checksum);
    CHECK(again->layout == s.layout);
    CHECK(again->live == s.live);
    CHECK(again->timing == s.timing);
    CHECK(again->options == s.options);
    CHECK(again->error_texts == s.error_texts);
    CHECK(again->error_log.size() == s.error_log.size());
    CHECK(again->errors_occurred == s.errors_occurred);
  }
  auto a = load_fixture("commissioned-axis.json");
  auto b = load_fixture("used-spare.json");
  CHECK(a.params.size() >= 24);
  std::set<sim::Layer> layers;
  for (const auto& [u, p] : a.params) {
    CHECK(b.params.count(u) == 1);
    if (p.modified()) layers.insert(sim::layer_of(u));
  }
  CHECK(layers.size() == 4);
  CHECK(a.curves_flash.size() == 2);
  CHECK(a.curves_flash.at(1).info.size() == 70);
  CHECK(a.curves_flash.at(1).data.size() == 84);
  CHECK(a.ct_flash.size() == 5);
  CHECK(a.ct_flash.at(2) ==
        from_hex("01 A7 FF FF 00 01 40 42 0F 00 20 A1 07 00 40 0D 03 00 40 0D 03 00"
                 "00 00 00 00 00 00 00 00 00 00 00 00 00 00 00 00 55 6E 6E 61 6D 65 64 00"
                 "00 00 00 00 00 00 00 00 FF FF FF FF FF FF FF FF FF FF")
            .value());
  CHECK(b.curves_flash.count(7) == 1);
  CHECK(b.ct_flash.size() == 2);
  CHECK(b.ct_flash.count(3) == 1);
  CHECK(b.ct_flash.count(9) == 1);

  // The family and the reading options that a state file holds only when set
  // come back from it.
  a.options.family = "B1100";
  a.options.stale_block_padding = true;
  a.options.address_usage_request = true;
  auto set = sim::from_json(sim::to_json(a));
  REQUIRE(set.ok());
  CHECK(set->options == a.options);
  a.options = load_fixture("commissioned-axis.json").options;

  // File save/load after changes made over the wire.
  SimHarness h(a);
  CHECK(h.ask_iv(make_cfg_write(kId, 0x3010, 4242), 0x51).state == 0x00);
  const auto path = (std::filesystem::temp_directory_path() / "lmcfg-sim-roundtrip.json").string();
  REQUIRE(sim::save_state(h.drive->state(), path).ok());
  auto back = sim::load_state(path);
  REQUIRE(back.ok());
  CHECK(back->params.at(0x3010).rom == 4242u);
  std::remove(path.c_str());

  auto bad = sim::from_json(nlohmann::json{{"format", "lmcfg-sim-state"}, {"version", 2}});
  REQUIRE_FALSE(bad.ok());
  CHECK(bad.error().code == make_error_code(Errc::unsupported_version));
  auto bad2 = sim::from_json(nlohmann::json::parse(
      R"({"format":"lmcfg-sim-state","version":1,"parameters":[{"upid":"zz"}]})"));
  REQUIRE_FALSE(bad2.ok());
  CHECK(bad2.error().code == make_error_code(Errc::parse_error));
}

TEST_CASE("sim state file: what it refuses is named with the field", "[sim][state_file]") {
  auto format = sim::from_json(nlohmann::json{{"format", "other"}, {"version", 1}});
  REQUIRE_FALSE(format.ok());
  CHECK(format.error().code == make_error_code(Errc::parse_error));
  CHECK(format.error().message == "sim state: format: expected \"lmcfg-sim-state\"");
  auto version = sim::from_json(nlohmann::json{{"format", "lmcfg-sim-state"}, {"version", 2}});
  REQUIRE_FALSE(version.ok());
  CHECK(version.error().message == "sim state version 2 (this build reads 1)");
  auto twice = sim::from_json(nlohmann::json::parse(
      R"({"format":"lmcfg-sim-state","version":1,"parameters":[{"upid":"13A2"},{"upid":"13a2"}]})"));
  REQUIRE_FALSE(twice.ok());
  CHECK(twice.error().message == "sim state: parameters: UPID 13A2 given twice");
  auto no_upid = sim::from_json(nlohmann::json::parse(
      R"({"format":"lmcfg-sim-state","version":1,"parameters":[{"name":"x"}]})"));
  REQUIRE_FALSE(no_upid.ok());
  CHECK(no_upid.error().message == "sim state: parameters: entry without upid");
  auto macid =
      sim::from_json(nlohmann::json{{"format", "lmcfg-sim-state"}, {"version", 1}, {"macid", 256}});
  REQUIRE_FALSE(macid.ok());
  CHECK(macid.error().message == "sim state: macid: exceeds FFh");
  auto family = sim::from_json(nlohmann::json::parse(
      R"({"format":"lmcfg-sim-state","version":1,"options":{"family":"A1100"}})"));
  REQUIRE_FALSE(family.ok());
  CHECK(family.error().message ==
        "sim state: options.family: expected one of E1100, B1100, C1100, E1200, E1400");
  // The defaults of a file that gives nothing but its format.
  auto bare = sim::from_json(nlohmann::json{{"format", "lmcfg-sim-state"}, {"version", 1}});
  REQUIRE(bare.ok());
  CHECK(bare->macid == 0x11);
  CHECK(bare->params.empty());
}

TEST_CASE("sim state file: loading, saving and a line of drives with distinct MACIDs",
          "[sim][state_file]") {
  auto missing = sim::load_state("/nonexistent/lmcfg/state.json");
  REQUIRE_FALSE(missing.ok());
  CHECK(missing.error().code == make_error_code(Errc::file_error));
  CHECK(missing.error().message == "cannot open sim state file /nonexistent/lmcfg/state.json");

  test::ScratchDir dir("sim-state");
  const auto bad = (dir.path / "bad.json").string();
  test::spit(bad, R"({"format":"lmcfg-sim-state","version":1,"macid":"zz"})");
  auto r = sim::load_state(bad);
  REQUIRE_FALSE(r.ok());
  CHECK(r.error().code == make_error_code(Errc::parse_error));
  CHECK(r.error().message == bad + ": sim state: macid: 'zz' is not a number");

  // Saved through a temporary file renamed over the target: none left behind.
  const auto out = (dir.path / "drive.json").string();
  auto axis = load_fixture("commissioned-axis.json");
  REQUIRE(sim::save_state(axis, out).ok());
  CHECK_FALSE(std::filesystem::exists(out + ".tmp"));
  auto back = sim::load_state(out);
  REQUIRE(back.ok());
  CHECK(back->params == axis.params);
  auto unwritable = sim::save_state(axis, (dir.path / "no" / "x.json").string());
  REQUIRE_FALSE(unwritable.ok());
  CHECK(unwritable.error().message ==
        "cannot write " + (dir.path / "no" / "x.json").string() + ".tmp");

  // Two drives of one line answering at the same MACID are refused.
  const auto a = fixture_path("commissioned-axis.json");
  const auto b = fixture_path("used-spare.json");
  auto same = sim::load_line({a, b});
  REQUIRE_FALSE(same.ok());
  CHECK(same.error().code == make_error_code(Errc::invalid_argument));
  CHECK(same.error().message == b + ": MACID 11h is already used by " + a + " on this line");
  axis.macid = 0x12;
  const auto other = (dir.path / "axis-12.json").string();
  REQUIRE(sim::save_state(axis, other).ok());
  auto line = sim::load_line({a, other});
  REQUIRE(line.ok());
  REQUIRE(line->size() == 2);
  CHECK((*line)[0].macid == 0x11);
  CHECK((*line)[1].macid == 0x12);
}

}  // namespace sim_test_state_file
