// lmcfg over LinUDP end to end: `lmcfg sim --linudp --udp 127.0.0.1:0` and
// backup, diff, restore with verify, default, undo, get over
// linudp://127.0.0.1:PORT; the same backup as over LinRS; the exact message
// and exit code of no answer, another master, a refused command and a restore
// cut in the middle (docs/linudp.md).
#include <catch2/catch.hpp>
#include <filesystem>
#include <fstream>

#include "e2e_support.hpp"
#include "files.hpp"
#include "subprocess.hpp"

// This file's own namespace: the test binary is a unity build (tests/CMakeLists.txt).
namespace tools_test_linudp_cli {

using namespace lmcfg;
namespace fs = std::filesystem;

namespace {

bool contains(const std::string& s, const std::string& part) {
  return s.find(part) != std::string::npos;
}

struct UdpSim {
  std::unique_ptr<test::Child> child;
  std::string port;
  std::string options_line;
  UdpSim(const fs::path& state, const std::vector<std::string>& fields = {}) {
    std::vector<std::string> argv{LMCFG_TOOL_PATH, "sim",     "--linudp",     "--udp",
                                  "127.0.0.1:0",   "--state", state.string(), "--fast"};
    for (const auto& f : fields) {
      argv.push_back("--linudp-field");
      argv.push_back(f);
    }
    child = std::make_unique<test::Child>(argv);
    port = child->read_line();
    options_line = child->read_line();
  }
  std::string url() const { return "linudp://127.0.0.1:" + port; }
};

}  // namespace

TEST_CASE("linudp cli: backup, diff, restore with verify, default and undo against lmcfg sim",
          "[linudp][cli][e2e]") {
  test::ScratchDir dir("linudp-cli");
  fs::copy_file(test::sim_fixture("commissioned-axis.json"), dir.path / "axis.sim.json");
  fs::copy_file(test::sim_fixture("used-spare.json"), dir.path / "spare.sim.json");
  UdpSim axis(dir.path / "axis.sim.json");
  UdpSim spare(dir.path / "spare.sim.json");
  REQUIRE_FALSE(axis.port.empty());
  CHECK(axis.options_line == "link options: --port " + axis.url());

  auto b = test::run_tool_in(dir.path, "backup --quiet --port " + axis.url() + " -o axis.json");
  INFO(b.err);
  REQUIRE(b.exit_code == 0);
  auto cfg = nlohmann::json::parse(test::slurp(dir.path / "axis.json"));
  CHECK(cfg["curves"].size() == 2);

  CHECK(
      test::run_tool_in(dir.path, "diff axis.json drive --quiet --port " + axis.url()).exit_code ==
      0);
  CHECK(
      test::run_tool_in(dir.path, "diff axis.json drive --quiet --port " + spare.url()).exit_code ==
      1);
  auto r = test::run_tool_in(
      dir.path, "restore axis.json --yes --quiet --include-comm --port " + spare.url());
  INFO(r.err);
  REQUIRE(r.exit_code == 0);
  CHECK(
      test::run_tool_in(dir.path, "diff axis.json drive --quiet --port " + spare.url()).exit_code ==
      0);

  auto d = test::run_tool_in(dir.path, "default --curves --yes --quiet --port " + spare.url());
  INFO(d.err);
  REQUIRE(d.exit_code == 0);
  CHECK(
      test::run_tool_in(dir.path, "diff axis.json drive --quiet --port " + spare.url()).exit_code ==
      1);
  auto u = test::run_tool_in(dir.path, "undo --yes --quiet --port " + spare.url());
  INFO(u.err);
  REQUIRE(u.exit_code == 0);
  CHECK(
      test::run_tool_in(dir.path, "diff axis.json drive --quiet --port " + spare.url()).exit_code ==
      0);
}

TEST_CASE("linudp cli: a backup over LinUDP and one over LinRS of the same drive compare identical",
          "[linudp][cli][e2e]") {
  test::ScratchDir dir("linudp-same");
  fs::copy_file(test::sim_fixture("commissioned-axis.json"), dir.path / "axis.sim.json");
  UdpSim axis(dir.path / "axis.sim.json");
  REQUIRE(
      test::run_tool_in(dir.path, "backup -q --port " + axis.url() + " -o udp.json").exit_code ==
      0);
  REQUIRE(test::run_tool_in(dir.path, "backup -q --port sim:axis.sim.json -o rs.json").exit_code ==
          0);
  auto d = test::run_tool_in(dir.path, "diff udp.json rs.json");
  INFO(d.out << d.err);
  CHECK(d.exit_code == 0);
}

TEST_CASE("linudp cli: the exact messages and exit codes of the link failures",
          "[linudp][cli][e2e]") {
  test::ScratchDir dir("linudp-fail");
  fs::copy_file(test::sim_fixture("commissioned-axis.json"), dir.path / "axis.sim.json");

  SECTION("another master holds the drive: exit 4") {
    UdpSim held(dir.path / "axis.sim.json", {"held_by_other_master"});
    auto r = test::run_tool_in(dir.path, "backup -q --port " + held.url() + " -o x.json");
    CHECK(r.exit_code == 4);
    CHECK(contains(r.err, "the LinUDP drive at udp 127.0.0.1:" + held.port +
                              " answers with all-zero telegrams: it is held by another master "
                              "(LinMot-Talk or another LinUDP client, LinUDP V2 §5); "
                              "disconnect that master and try again"));
    CHECK_FALSE(fs::exists(dir.path / "x.json"));
  }
  SECTION("no answer: exit 4") {
    UdpSim gone(dir.path / "axis.sim.json", {"lose_request_every=1"});
    auto r = test::run_tool_in(dir.path, "backup -q --port " + gone.url() + " -o x.json");
    CHECK(r.exit_code == 4);
    CHECK(contains(r.err, "no answer from the LinUDP drive at udp 127.0.0.1:" + gone.port +
                              " to no operation (00h) (count 2, sent 7 times, "));
    CHECK(contains(r.err, "check the address and port (linudp://HOST[:PORT], drive port 49360)"));
  }
  SECTION("a refused command: exit 5") {
    UdpSim axis(dir.path / "axis.sim.json");
    auto r = test::run_tool_in(dir.path, "get 5555 --rom --port " + axis.url());
    CHECK(r.exit_code == 5);
    CHECK(contains(r.err,
                   "refused read ROM value (10h) for UPID 5555h: status C0h UPID error "
                   "(LinUDP V2 p14)"));
  }
  SECTION("a restore cut in the middle: exit 4") {
    fs::copy_file(test::sim_fixture("used-spare.json"), dir.path / "spare.sim.json");
    UdpSim axis(dir.path / "axis.sim.json");
    REQUIRE(
        test::run_tool_in(dir.path, "backup -q --port " + axis.url() + " -o a.json").exit_code ==
        0);
    {
      UdpSim cut(dir.path / "spare.sim.json", {"silent_after_writes=5"});
      auto r = test::run_tool_in(
          dir.path,
          "restore a.json --yes -q --recover-timeout-s 1 --long-timeout-s 2 --port " + cut.url());
      INFO(r.err);
      CHECK(r.exit_code == 4);
      CHECK(contains(r.err, "no answer from the LinUDP drive at udp 127.0.0.1:" + cut.port));
    }
  }
}

TEST_CASE(
    "linudp cli: link refuses a LinUDP port and sends nothing, scan probes it (no drive: exit 1)",
    "[linudp][cli]") {
  test::ScratchDir dir("linudp-refuse");
  auto s = test::run_tool_in(dir.path, "scan --quiet --port linudp://127.0.0.1:9");
  CHECK(s.exit_code == 1);
  CHECK(s.out == "1 address(es) probed: 0 answered, 0 held by another master, 1 silent\n");
  auto l = test::run_tool_in(dir.path, "link --port linudp://127.0.0.1:9 --set-baud 115200 --yes");
  CHECK(l.exit_code == 2);
  CHECK(contains(l.err,
                 "--port linudp://127.0.0.1:9 is a LinUDP drive: lmcfg link changes the "
                 "LinRS settings of seed 003 §15"));
  auto p = test::run_tool_in(dir.path, "info --port linudp://");
  CHECK(p.exit_code == 2);
  CHECK(contains(p.err,
                 "port 'linudp://' is not linudp://HOST[:PORT] (an IPv4 address or name, "
                 "PORT 1..65535)"));
}

TEST_CASE("linudp cli: a fleet backup of two LinUDP drives, each on a line of its own",
          "[linudp][cli][fleet]") {
  test::ScratchDir dir("linudp-fleet");
  fs::copy_file(test::sim_fixture("commissioned-axis.json"), dir.path / "a.sim.json");
  fs::copy_file(test::sim_fixture("used-spare.json"), dir.path / "b.sim.json");
  UdpSim a(dir.path / "a.sim.json", {"unacknowledged_saves", "stale_echo_every=3"});
  UdpSim b(dir.path / "b.sim.json", {"lose_reply_every=25", "end_on_extra_read"});
  test::spit(dir.path / "plant.toml",
             "[[line]]\nname = \"cell1\"\nport = \"" + a.url() +
                 "\"\n[[line.drive]]\nname = \"cell1/gripper\"\nlabels = { machine = \"cell1\" }\n"
                 "[[line]]\nname = \"cell2\"\nport = \"" +
                 b.url() + "\"\n[[line.drive]]\nname = \"cell2/lift\"\n");
  auto check = test::run_tool_in(dir.path, "fleet check plant.toml");
  INFO(check.err);
  CHECK(check.exit_code == 0);
  auto r = test::run_tool_in(dir.path, "fleet backup plant.toml --archive arch");
  INFO(r.err);
  CHECK(r.exit_code == 0);
  CHECK(
      contains(r.err, "[cell1 1/1] cell1/gripper: read 16 parameter(s), 2 curve(s), 5 CT entries"));
  CHECK(contains(r.err, "[cell2 1/1] cell2/lift: read 10 parameter(s), 1 curve(s), 2 CT entries"));
}

}  // namespace tools_test_linudp_cli
