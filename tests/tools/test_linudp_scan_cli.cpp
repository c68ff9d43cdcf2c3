// `lmcfg scan --port linudp://RANGE` end to end: simulated LinUDP drives
// (`lmcfg sim --linudp --udp 127.0.0.N:PORT`, 127.0.0.0/8 all loop back) on
// several loopback addresses, one held by another master (LinUDP V2 §5,
// C1250 notes), one address with nobody; the exact report, the bound on the range and
// the options a LinUDP scan refuses (docs/linudp.md "Scan").
#include <catch2/catch.hpp>
#include <filesystem>
#include <fstream>

#include "e2e_support.hpp"
#include "files.hpp"
#include "subprocess.hpp"

// This file's own namespace: the test binary is a unity build (tests/CMakeLists.txt).
namespace tools_test_linudp_scan_cli {

using namespace lmcfg;
namespace fs = std::filesystem;

namespace {

struct UdpSim {
  std::unique_ptr<test::Child> child;
  std::string port;
  UdpSim(const fs::path& state, const std::string& host_port,
         const std::vector<std::string>& fields = {}) {
    std::vector<std::string> argv{LMCFG_TOOL_PATH, "sim",     "--linudp",     "--udp",
                                  host_port,       "--state", state.string(), "--fast"};
    for (const auto& f : fields) {
      argv.push_back("--linudp-field");
      argv.push_back(f);
    }
    child = std::make_unique<test::Child>(argv);
    port = child->read_line();
    (void)child->read_line();  // the link options line
  }
};

// The firmware version UPIDs (LinUDP DLL: RAM 0034h, 0035h) added to a state file.
void add_firmware(const fs::path& state, unsigned major, unsigned minor) {
  auto j = nlohmann::json::parse(test::slurp(state));
  for (auto [upid, v] : {std::pair<const char*, unsigned>{"0034", major}, {"0035", minor}}) {
    j["parameters"].push_back({{"upid", upid},
                               {"name", "firmware version (synthetic)"},
                               {"type", "UINT16"},
                               {"address_usage", "0001"},
                               {"min", 0},
                               {"max", 65535},
                               {"default", 0},
                               {"rom", 0},
                               {"ram", v}});
  }
  std::ofstream(state) << j.dump(2);
}

}  // namespace

TEST_CASE("linudp scan cli: drives on 127.0.0.1-4, one held by another master, one address silent",
          "[linudp][cli][scan]") {
  test::ScratchDir dir("linudp-scan");
  fs::copy_file(test::sim_fixture("commissioned-axis.json"), dir.path / "axis.sim.json");
  fs::copy_file(test::sim_fixture("used-spare.json"), dir.path / "spare.sim.json");
  fs::copy_file(test::sim_fixture("used-spare.json"), dir.path / "held.sim.json");
  add_firmware(dir.path / "axis.sim.json", 0x06, 0x0A);  // LinUDP DLL: 060Ah = LT 6.10
  UdpSim axis(dir.path / "axis.sim.json", "127.0.0.1:0");
  REQUIRE_FALSE(axis.port.empty());
  const std::string p = axis.port;
  UdpSim held(dir.path / "held.sim.json", "127.0.0.3:" + p, {"held_by_other_master"});
  UdpSim spare(dir.path / "spare.sim.json", "127.0.0.4:" + p);
  REQUIRE(held.port == p);
  REQUIRE(spare.port == p);

  auto r = test::run_tool_in(dir.path, "scan --port linudp://127.0.0.1-4:" + p);
  INFO(r.err);
  CHECK(r.exit_code == 0);
  CHECK(r.out ==
        "drive at 127.0.0.1:" + p +
            ": state 8 Operation Enabled (state var 08C2h), status word 4C37h, error 0000h, "
            "firmware 060Ah; link options: --port linudp://127.0.0.1:" +
            p +
            "\n"
            "drive at 127.0.0.3:" +
            p +
            ": held by another master (all-zero replies, LinUDP V2 §5)\n"
            "drive at 127.0.0.4:" +
            p +
            ": state 8 Operation Enabled (state var 08C2h), status word 4C37h, error 0000h, "
            "firmware version not readable (RAM 0034h/0035h refused); link options: --port "
            "linudp://127.0.0.4:" +
            p +
            "\n"
            "4 address(es) probed: 2 answered, 1 held by another master, 1 silent\n");
  CHECK(r.err.rfind("lmcfg scan: 4 address(es), 7 datagrams, ", 0) == 0);

  auto j = test::run_tool_in(dir.path, "scan --json --port linudp://127.0.0.2-3:" + p);
  REQUIRE(j.exit_code == 0);
  auto doc = nlohmann::json::parse(j.out);
  CHECK(doc["addresses"][0]["answer"] == "silent");
  CHECK(doc["addresses"][1]["answer"] == "held_by_other_master");
  CHECK(doc["datagrams"] == 2);

  auto none = test::run_tool_in(dir.path, "scan --quiet --port linudp://127.0.0.2:" + p);
  CHECK(none.exit_code == 1);
  CHECK(none.out == "1 address(es) probed: 0 answered, 0 held by another master, 1 silent\n");
}

TEST_CASE("linudp scan cli: the bound on the range and the options it refuses",
          "[linudp][cli][scan]") {
  test::ScratchDir dir("linudp-scan-bad");
  auto big = test::run_tool_in(dir.path, "scan --port linudp://10.8.0.0/23");
  CHECK(big.exit_code == 2);
  CHECK(big.out.empty());
  CHECK(big.err ==
        "lmcfg scan: --port linudp://10.8.0.0/23: 510 addresses, more than the 256 a LinUDP scan "
        "probes (one /24); name a smaller range\n");
  auto ids = test::run_tool_in(dir.path, "scan --port linudp://10.8.7.0/24 --from 1");
  CHECK(ids.exit_code == 2);
  CHECK(ids.err ==
        "lmcfg scan: --from/--to and --baud name MACIDs and rates of a LinRS line; a LinUDP scan "
        "takes its addresses from --port linudp://RANGE\n");
}

}  // namespace tools_test_linudp_scan_cli
