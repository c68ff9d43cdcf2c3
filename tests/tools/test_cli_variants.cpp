// docs/reliability.md, "Done when": simulated drive variants with each checksum
// mode, CRC variant and coverage, with a non-factory default-response layout,
// and with a layer default taking several seconds: every drive-facing
// subcommand (info, get, set, backup, diff against the drive, default,
// restore, scan) works against each with the matching options, or by
// detection (scan, --response-layout auto).
//
// The drives are `--port sim:FILE` (in process, virtual clock: a layer default
// of 8 s costs no wall time); the state file carries the drive from one
// command to the next. The pty path is covered by test_cli_scan_first_steps.cpp.
#include <sys/wait.h>

#include <catch2/catch.hpp>
#include <chrono>
#include <filesystem>
#include <fstream>
#include <nlohmann/json.hpp>
#include <sstream>

#include "sim/state_file.hpp"
#include "subprocess.hpp"

// This file's own namespace: the test binary is a unity build (tests/CMakeLists.txt).
namespace tools_test_cli_variants {

using namespace lmcfg;
namespace fs = std::filesystem;

namespace {

using Run = test::ToolRun;
using test::slurp;

struct TempDir : test::ScratchDir {
  TempDir() : ScratchDir("variants") {}
};

Run tool(const fs::path& dir, const std::string& args) { return test::run_tool_in(dir, args); }

struct Variant {
  std::string name;
  nlohmann::json state;   // the drive's state file
  std::string options;    // the link options that match it (besides --port and --id)
  std::string scan_says;  // what scan must print as the options to use ("" = not checked)
  bool slow_default = false;
};

// The demo axis keeps MACID 11h and 57600 Bd: its ROM selects them "By
// Parameter" (200Eh, 206Ch), and the resets of `default` and `restore` apply
// the ROM's communication values.
nlohmann::json demo_axis() {
  auto st =
      sim::load_state(std::string(LMCFG_SOURCE_DIR) + "/tests/fixtures/sim/commissioned-axis.json");
  REQUIRE(st.ok());
  return sim::to_json(*st);
}

std::vector<Variant> variants() {
  std::vector<Variant> v;
  {
    Variant x{"factory (no checksum)", demo_axis(), "", "--checksum none"};
    v.push_back(x);
  }
  struct Mode {
    const char* state_mode;
    const char* crc_init;  // nullptr: not a CRC
    const char* option;
  };
  const Mode modes[] = {{"add", nullptr, "add"},
                        {"crc_ccitt", "FFFF", "crc-ffff"},
                        {"crc_ccitt", "0000", "crc-0000"},
                        {"crc_kermit", "0000", "crc-kermit"}};
  const std::pair<const char*, const char*> coverages[] = {
      {"id_through_data", "id"}, {"start_through_data", "start"}, {"data_only", "data"}};
  for (const auto& m : modes) {
    for (const auto& [coverage, cov_option] : coverages) {
      Variant x;
      x.name = std::string("checksum ") + m.option + ", coverage " + cov_option;
      x.state = demo_axis();
      x.state["checksum"]["mode"] = m.state_mode;
      x.state["checksum"]["coverage"] = coverage;
      if (m.crc_init) x.state["checksum"]["crc_init"] = m.crc_init;
      x.options = std::string(" --checksum ") + m.option + " --checksum-coverage " + cov_option;
      // scan prints the coverage only when it is not the default (id).
      x.scan_says =
          std::string("--checksum ") + m.option +
          (std::string(cov_option) == "id" ? ""
                                           : std::string(" --checksum-coverage ") + cov_option);
      v.push_back(std::move(x));
    }
  }
  {
    // §6.1.1.1: the default response without State Var, with the warn word
    // and the second monitoring channel; the tools detect it from its length.
    Variant x{"non-factory default response (auto)", demo_axis(), "", "--checksum none"};
    x.state["default_response"]["state_var"] = false;
    x.state["default_response"]["warn_word"] = true;
    x.state["default_response"]["monitoring_2"] = true;
    v.push_back(x);
    Variant y = x;
    y.name = "non-factory default response (--response-layout)";
    y.options = " --response-layout comm_state,status_word,warn_word,monitoring_1,monitoring_2";
    v.push_back(y);
  }
  {
    // §10.4 "could be more than 1 s": every layer default takes 8 s.
    Variant x{"layer default of 8 s", demo_axis(), "", "--checksum none", true};
    x.state["timing_us"]["defaulting"] = 8'000'000;
    v.push_back(x);
  }
  return v;
}

}  // namespace

TEST_CASE("docs/reliability.md: every subcommand works against every drive variant",
          "[cli][variants]") {
  for (const auto& variant : variants()) {
    DYNAMIC_SECTION(variant.name) {
      TempDir d;
      std::ofstream(d.path / "drive.json") << variant.state.dump(2);
      const std::string link = " --port sim:drive.json --id 0x11" + variant.options;

      auto info = tool(d.path, "info" + link);
      INFO("info: " << info.err);
      CHECK(info.exit_code == 0);
      CHECK_FALSE(info.out.empty());

      auto get = tool(d.path, "get 13A2 --rom --json" + link);
      INFO("get: " << get.err);
      REQUIRE(get.exit_code == 0);
      const auto before = nlohmann::json::parse(get.out);
      CHECK(before["upid"] == "13A2");
      const long long old_value = before["raw"].get<long long>();
      const long long new_value = old_value == 16 ? 17 : 16;

      auto set = tool(d.path, "set 13A2 " + std::to_string(new_value) + " --rom --stop-mc" + link);
      INFO("set: " << set.err);
      CHECK(set.exit_code == 0);
      auto after = tool(d.path, "get 13A2 --rom --json" + link);
      REQUIRE(after.exit_code == 0);
      CHECK(nlohmann::json::parse(after.out)["raw"] == new_value);

      auto backup = tool(d.path, "backup -o a.json --quiet" + link);
      INFO("backup: " << backup.err);
      REQUIRE(backup.exit_code == 0);
      const auto file = nlohmann::json::parse(slurp(d.path / "a.json"));
      CHECK_FALSE(file.empty());

      auto same = tool(d.path, "diff a.json drive" + link);
      INFO("diff (same): " << same.out << same.err);
      CHECK(same.exit_code == 0);
      CHECK(same.out.find("\nidentical\n") != std::string::npos);

      auto def = tool(d.path, "default --layers mc --yes" + link);
      INFO("default: " << def.err);
      CHECK(def.exit_code == 0);
      if (variant.slow_default) {
        // Progress while the 8 s default runs (stderr is not a terminal here).
        CHECK(def.err.find("lmcfg: still defaulting layer MC: 5 s (waiting up to 120 s; "
                           "--long-timeout-s)\n") != std::string::npos);
      }
      auto defaulted = tool(d.path, "get 13A2 --rom --json" + link);
      REQUIRE(defaulted.exit_code == 0);
      CHECK(nlohmann::json::parse(defaulted.out)["raw"] != new_value);

      auto differs = tool(d.path, "diff a.json drive" + link);
      INFO("diff (after default): " << differs.err);
      CHECK(differs.exit_code == 1);
      CHECK(differs.out.find("13A2") != std::string::npos);

      auto restore = tool(d.path, "restore a.json --yes" + link);
      INFO("restore: " << restore.out << restore.err);
      CHECK(restore.exit_code == 0);
      CHECK(restore.err.find("verified: the drive matches a.json") != std::string::npos);

      auto again = tool(d.path, "restore a.json --yes" + link);
      INFO("restore again: " << again.out << again.err);
      CHECK(again.exit_code == 0);
      CHECK(again.out == "nothing to do: the drive already matches a.json\n");

      auto restored = tool(d.path, "diff a.json drive" + link);
      CHECK(restored.exit_code == 0);
      CHECK(restored.out.find("\nidentical\n") != std::string::npos);
      auto value = tool(d.path, "get 13A2 --rom --json" + link);
      REQUIRE(value.exit_code == 0);
      CHECK(nlohmann::json::parse(value.out)["raw"] == new_value);

      // scan knows nothing of the variant: it finds the drive and names the
      // options (MACIDs 10h..12h only, to keep it short: --from/--to). Over
      // the drive served on a pty (`lmcfg sim`, the state the commands above
      // left): the in-process sim: port does not answer scan's requests
      // without a checksum, so it finds only drives without one (below).
      // The simulated drive answers a request that lacks its checksum when
      // the next request's bytes complete the frame (a checksum error, C-state
      // framed with its checksum); its 20 ms byte-to-byte receive timeout
      // would drop the partial frame first whenever the next request comes
      // later (a loaded machine, a longer per-ID deadline), so it is switched
      // off for the scan (timing_us.rx_timeout 0).
      const std::string want = "--baud 57600 --id 0x11 " + variant.scan_says + "\n";
      {
        auto served = nlohmann::json::parse(slurp(d.path / "drive.json"));
        served["timing_us"]["rx_timeout"] = 0;
        std::ofstream(d.path / "served.json") << served.dump(2);
        test::Child sim({LMCFG_TOOL_PATH, "sim", "--state", (d.path / "served.json").string()});
        const std::string pty = sim.read_line();
        REQUIRE(pty.rfind("/dev/", 0) == 0);
        // --timeout-ms 100: the per-ID deadline, also of the confirming
        // request, with room for a pty server on a loaded machine.
        auto scan = tool(
            d.path, "scan --port " + pty + " --baud 57600 --from 0x10 --to 0x12 --timeout-ms 100");
        INFO("scan (pty): " << scan.out << scan.err);
        CHECK(scan.exit_code == 0);
        CHECK(scan.out.find(want) != std::string::npos);
      }
      if (variant.scan_says == "--checksum none") {
        auto scan =
            tool(d.path, "scan --port sim:drive.json --baud 57600 --from 0x10 --to 0x12 --quiet");
        INFO("scan (sim:): " << scan.out << scan.err);
        CHECK(scan.exit_code == 0);
        CHECK(scan.out.find(want) != std::string::npos);
      }
    }
  }
}

}  // namespace tools_test_cli_variants
