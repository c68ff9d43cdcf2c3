// Issue 5 acceptance, through the real `lmcfg` binary and real pseudo-terminals:
// two `lmcfg sim --pty` servers (a commissioned axis and a used spare), then
// backup -> diff against defaults -> restore onto the spare -> the spare's ROM
// values, flash curves and flash command table equal the source's.
#include <catch2/catch.hpp>
#include <filesystem>
#include <fstream>
#include <nlohmann/json.hpp>
#include <set>

#include "e2e_support.hpp"
#include "subprocess.hpp"

using namespace lmcfg;
namespace fs = std::filesystem;

namespace {

fs::path temp_dir(const std::string& name) {
  auto d = fs::temp_directory_path() / ("lmcfg-" + name + "-" + std::to_string(::getpid()));
  fs::remove_all(d);
  fs::create_directories(d);
  return d;
}

std::map<std::uint16_t, std::uint32_t> modified_rom(const sim::DriveState& s) {
  std::map<std::uint16_t, std::uint32_t> m;
  for (const auto& [upid, p] : s.params)
    if (p.modified()) m[upid] = p.rom;
  return m;
}

std::string slurp(const fs::path& p) {
  std::ifstream in(p);
  return std::string(std::istreambuf_iterator<char>(in), {});
}

}  // namespace

TEST_CASE("e2e over pty: backup, diff defaults, restore onto a used spare, spare equals source", "[e2e][pty]") {
  const auto dir = temp_dir("pty");
  fs::copy_file(test::sim_fixture("commissioned-axis.json"), dir / "axis.sim.json");
  fs::copy_file(test::sim_fixture("used-spare.json"), dir / "spare.sim.json");
  const std::string tool = LMCFG_TOOL_PATH;
  test::Child axis({tool, "sim", "--state", (dir / "axis.sim.json").string(), "--pty", "--fast", "--save-on-exit"});
  test::Child spare({tool, "sim", "--state", (dir / "spare.sim.json").string(), "--pty", "--fast", "--save-on-exit"});
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
    if (d["kind"] == "parameter") listed.insert(static_cast<std::uint16_t>(std::stoul(d["upid"].get<std::string>(), nullptr, 16)));
  auto source_state = sim::load_state(test::sim_fixture("commissioned-axis.json"));
  REQUIRE(source_state.ok());
  std::set<std::uint16_t> modified;
  for (const auto& [upid, v] : modified_rom(*source_state)) modified.insert(upid);
  CHECK(listed == modified);

  // A dry run writes nothing.
  const auto dry_trace = dir / "dry.trace";
  REQUIRE(test::run_tool("restore " + file + " --port " + spare_tty + " --dry-run --quiet --trace " + dry_trace.string() +
                         " > /dev/null") == 0);

  REQUIRE(test::run_tool("restore " + file + " --port " + spare_tty + " --include-comm --quiet --yes") == 0);
  REQUIRE(test::run_tool("diff " + file + " drive --port " + spare_tty + " --quiet --ignore-unit > /dev/null") == 0);

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
  test::Child server(
      {LMCFG_TOOL_PATH, "sim", "--state", (dir / "axis.sim.json").string(), "--tcp", "127.0.0.1:0", "--fast"});
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
