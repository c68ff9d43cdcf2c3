// README acceptance, through the real `lmcfg` binary and real pseudo-terminals:
// two `lmcfg sim --pty` servers (a commissioned axis and a used spare), then
// backup -> diff against defaults -> restore onto the spare -> the spare's ROM
// values, flash curves and flash command table equal the source's.
#include <sys/wait.h>

#include <catch2/catch.hpp>
#include <filesystem>
#include <fstream>
#include <nlohmann/json.hpp>
#include <set>
#include <sstream>

#include "client/client.hpp"
#include "codec/frame.hpp"
#include "common/bytes.hpp"
#include "e2e_support.hpp"
#include "files.hpp"
#include "subprocess.hpp"
#include "trace_support.hpp"

// This file's own namespace: the test binary is a unity build (tests/CMakeLists.txt).
namespace tools_test_e2e_cli_pty {

using namespace lmcfg;
using test::slurp;
using test::temp_dir;
namespace fs = std::filesystem;

namespace {

std::map<std::uint16_t, std::uint32_t> modified_rom(const sim::DriveState& s) {
  std::map<std::uint16_t, std::uint32_t> m;
  for (const auto& [upid, p] : s.params)
    if (p.modified()) m[upid] = p.rom;
  return m;
}

}  // namespace

TEST_CASE("e2e over pty: backup, diff defaults, restore onto a used spare, spare equals source",
          "[e2e][pty]") {
  const auto dir = temp_dir("pty");
  fs::copy_file(test::sim_fixture("commissioned-axis.json"), dir / "axis.sim.json");
  fs::copy_file(test::sim_fixture("used-spare.json"), dir / "spare.sim.json");
  const std::string tool = LMCFG_TOOL_PATH;
  test::Child axis({tool, "sim", "--state", (dir / "axis.sim.json").string(), "--pty", "--fast",
                    "--save-on-exit"});
  test::Child spare({tool, "sim", "--state", (dir / "spare.sim.json").string(), "--pty", "--fast",
                     "--save-on-exit"});
  const std::string axis_tty = axis.read_line();
  const std::string spare_tty = spare.read_line();
  REQUIRE(axis_tty.rfind("/dev/pts/", 0) == 0);
  REQUIRE(spare_tty.rfind("/dev/pts/", 0) == 0);

  const std::string file = (dir / "axis.json").string();
  REQUIRE(test::run_tool("backup --quiet --port " + axis_tty + " -o " + file) == 0);

  // diff against defaults lists exactly the modified UPIDs of the source drive.
  const auto diff_out = dir / "diff.json";
  REQUIRE(test::run_tool("diff defaults " + file + " --json --quiet > " + diff_out.string()) == 1);
  auto report = nlohmann::json::parse(slurp(diff_out));
  std::set<std::uint16_t> listed;
  for (const auto& d : report["differences"])
    if (d["kind"] == "parameter")
      listed.insert(
          static_cast<std::uint16_t>(std::stoul(d["upid"].get<std::string>(), nullptr, 16)));
  auto source_state = sim::load_state(test::sim_fixture("commissioned-axis.json"));
  REQUIRE(source_state.ok());
  std::set<std::uint16_t> modified;
  for (const auto& [upid, v] : modified_rom(*source_state)) modified.insert(upid);
  CHECK(listed == modified);

  // A dry run writes nothing.
  const auto dry_trace = dir / "dry.trace";
  REQUIRE(test::run_tool("restore " + file + " --port " + spare_tty +
                         " --dry-run --quiet --trace " + dry_trace.string() + " > /dev/null") == 0);

  REQUIRE(test::run_tool("restore " + file + " --port " + spare_tty +
                         " --include-comm --quiet --yes") == 0);
  REQUIRE(test::run_tool("diff " + file + " drive --port " + spare_tty +
                         " --quiet --ignore-unit > /dev/null") == 0);

  CHECK(axis.stop() == 0);
  CHECK(spare.stop() == 0);
  auto spare_after = sim::load_state((dir / "spare.sim.json").string());
  REQUIRE(spare_after.ok());
  CHECK(modified_rom(*spare_after) == modified_rom(*source_state));
  CHECK(spare_after->curves_flash == source_state->curves_flash);
  CHECK(spare_after->ct_flash == source_state->ct_flash);
  fs::remove_all(dir);
}

TEST_CASE("e2e over TCP on loopback: backup through a serial-gateway style link", "[e2e][tcp]") {
  const auto dir = temp_dir("tcp");
  fs::copy_file(test::sim_fixture("commissioned-axis.json"), dir / "axis.sim.json");
  test::Child server({LMCFG_TOOL_PATH, "sim", "--state", (dir / "axis.sim.json").string(), "--tcp",
                      "127.0.0.1:0", "--fast"});
  const std::string port = server.read_line();
  REQUIRE_FALSE(port.empty());
  const std::string file = (dir / "axis.json").string();
  REQUIRE(test::run_tool("backup --quiet --port tcp://127.0.0.1:" + port + " -o " + file) == 0);
  auto cfg = nlohmann::json::parse(slurp(file));
  CHECK(cfg["format"] == "lmcfg-drive-config");
  CHECK(cfg["curves"].size() == 2);
  server.stop();
  fs::remove_all(dir);
}

TEST_CASE(
    "e2e over pty: restore checks the target's max, does nothing on a matching drive, and "
    "stops on SIGINT with exit 130 and converges when run again",
    "[e2e][pty][restore]") {
  const auto dir = temp_dir("pty-restore");
  fs::copy_file(test::sim_fixture("commissioned-axis.json"), dir / "axis.sim.json");
  fs::copy_file(test::sim_fixture("used-spare.json"), dir / "spare.sim.json");
  {  // the spare's firmware allows less for 13A2h than the file holds (40)
    auto j = nlohmann::json::parse(slurp(dir / "spare.sim.json"));
    for (auto& p : j["parameters"])
      if (p["upid"] == "13A2") p["max"] = 30;
    std::ofstream(dir / "low.sim.json") << j.dump(2);
  }
  const std::string tool = LMCFG_TOOL_PATH;
  const std::string env = "XDG_STATE_HOME=" + dir.string() + " ";
  test::Child axis({tool, "sim", "--state", (dir / "axis.sim.json").string(), "--pty", "--fast"});
  test::Child low({tool, "sim", "--state", (dir / "low.sim.json").string(), "--pty", "--fast"});
  const std::string axis_tty = axis.read_line(), low_tty = low.read_line();
  const std::string file = (dir / "axis.json").string();
  REQUIRE(test::run_tool("backup --quiet --port " + axis_tty + " -o " + file) == 0);

  for (const char* mode : {"--dry-run", "--yes"}) {
    const auto trace = dir / (std::string("low") + mode + ".trace");
    const auto err = dir / "low.err";
    CHECK(std::system((env + tool + " restore " + file + " --port " + low_tty + " " + mode +
                       " --trace " + trace.string() + " 2>" + err.string() + " >/dev/null")
                          .c_str()) == 3 * 256);
    CHECK(slurp(err).find("MC 13A2h") != std::string::npos);
    CHECK(test::traced_writes(trace) == 0);
  }

  const auto same = dir / "same.trace";
  const auto out = dir / "same.out";
  CHECK(std::system((env + tool + " restore " + file + " --port " + axis_tty + " --yes --trace " +
                     same.string() + " >" + out.string() + " 2>/dev/null")
                        .c_str()) == 0);
  CHECK(slurp(out) == "nothing to do: the drive already matches " + file + "\n");
  CHECK(test::traced_writes(same) == 0);

  // The spare is served with the modelled delays (flash save, reset), so a
  // restore takes seconds: SIGINT at several points, each followed by a rerun.
  int interrupted = 0;
  for (double at : {1.0, 2.5, 4.0}) {
    // A fresh used spare each time, served with the modelled delays.
    fs::copy_file(test::sim_fixture("used-spare.json"), dir / "spare.sim.json",
                  fs::copy_options::overwrite_existing);
    test::Child spare({tool, "sim", "--state", (dir / "spare.sim.json").string(), "--pty"});
    const std::string spare_tty = spare.read_line();
    INFO("SIGINT after " << at << " s");
    const auto err = dir / "int.err";
    const int rc = std::system((env + "timeout --preserve-status -s INT " + std::to_string(at) +
                                " " + tool + " restore " + file + " --port " + spare_tty +
                                " --yes --quiet 2>" + err.string())
                                   .c_str());
    const std::string said = slurp(err);
    INFO(said);
    if (WIFEXITED(rc) && WEXITSTATUS(rc) == 0) continue;  // finished before the signal
    CHECK(WEXITSTATUS(rc) == 130);
    CHECK(said.find("interrupted") != std::string::npos);
    ++interrupted;
    CHECK(test::run_tool("restore " + file + " --port " + spare_tty + " --yes --quiet") == 0);
    CHECK(test::run_tool("diff " + file + " drive --port " + spare_tty +
                         " --quiet --ignore-unit > /dev/null") == 0);
    CHECK(spare.stop() == 0);
  }
  CHECK(interrupted >= 2);
  CHECK(axis.stop() == 0);
  CHECK(low.stop() == 0);
}

}  // namespace tools_test_e2e_cli_pty
