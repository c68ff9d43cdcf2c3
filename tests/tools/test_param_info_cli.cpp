// get/set/info through the real tool binary and the built-in simulated drive
// (--port sim:STATE.json, a copy of tests/fixtures/sim/manual-drive.json):
// communication parameters need --include-comm, ROM writes need MC stopped
// (LinRS §10), and the --json reports validate against their schemas.
#include <unistd.h>

#include <catch2/catch.hpp>
#include <filesystem>
#include <string>

#include "test_config_support.hpp"

// This file's own namespace: the test binary is a unity build (tests/CMakeLists.txt).
namespace tools_test_param_info_cli {

using namespace lmcfg::config::testing;
namespace fs = std::filesystem;

namespace {

struct Rig {
  fs::path dir;
  std::string port;
  Rig() {
    static int n = 0;
    dir = fs::temp_directory_path() /
          ("lmcfg-paramcli-" + std::to_string(::getpid()) + "-" + std::to_string(n++));
    fs::remove_all(dir);
    fs::create_directories(dir);
    fs::copy_file(fs::path(LMCFG_SOURCE_DIR) / "tests" / "fixtures" / "sim" / "manual-drive.json",
                  dir / "drive.json");
    port = "--id 0x11 --baud 38400 --port 'sim:" + (dir / "drive.json").string() + "'";
  }
  ~Rig() {
    std::error_code ec;
    fs::remove_all(dir, ec);
  }
  struct Out {
    int rc = -1;
    std::string out, err;
  };
  Out tool(const std::string& args) const {
    const auto o = dir / "stdout.txt", e = dir / "stderr.txt";
    // Undo records of `set --rom` go below the test's own folder.
    const std::string cmd = "XDG_STATE_HOME='" + (dir / "state").string() + "' " +
                            std::string(LMCFG_TOOL_PATH) + " " + args + " " + port + " >'" +
                            o.string() + "' 2>'" + e.string() + "' </dev/null";
    const int rc = std::system(cmd.c_str());
    return Out{WIFEXITED(rc) ? WEXITSTATUS(rc) : -1, slurp(o), slurp(e)};
  }
  bool valid(const char* schema, const std::string& json) const {
    static const int ready =
        run("'" + (fs::path(LMCFG_SOURCE_DIR) / "scripts" / "install-node-deps.sh").string() +
            "'") == 0;
    if (!ready) return false;
    const auto f = dir / "report.json";
    spit(f, json);
    const auto ajv =
        fs::path(LMCFG_SOURCE_DIR) / "tools" / "node" / "node_modules" / ".bin" / "ajv";
    const auto s = fs::path(LMCFG_SOURCE_DIR) / "schemas" / schema;
    return run("'" + ajv.string() + "' validate --spec=draft2020 --strict=true -s '" + s.string() +
               "' -d '" + f.string() + "'") == 0;
  }
};

}  // namespace

TEST_CASE("seed003 §15 set: a communication parameter needs --include-comm and warns",
          "[cli][param]") {
  Rig r;
  auto refused = r.tool("set 2012 8");
  CHECK(refused.rc == 2);
  CHECK(refused.err ==
        "lmcfg set: 2012 Baud Rate Parameter Def is a communication parameter (baud rate, MACID, "
        "checksum or parity): writing it changes the link the drive answers on; add "
        "--include-comm to write it anyway; nothing written\n");
  auto ok = r.tool("set 2012 8 --include-comm");
  CHECK(ok.rc == 0);
  CHECK(ok.err.find("lmcfg set: warning: 2012 is a communication parameter: the link changes when "
                    "the value takes effect") != std::string::npos);
}

TEST_CASE("seed003 §10 §13.3 set --rom: MC must be stopped: --stop-mc, else refused with advice",
          "[cli][param]") {
  Rig r;
  auto refused = r.tool("set 13A2 16 --rom");
  CHECK(refused.rc == 2);
  CHECK(refused.err ==
        "lmcfg set: writing ROM needs the MC software stopped (seed 003 §10); add --stop-mc to "
        "stop it, write and start it again (the axis stops meanwhile), or write RAM only without "
        "--rom; nothing written\n");
  CHECK(r.tool("get 13A2 --rom --json").out.find("\"raw\":10,") != std::string::npos);
  auto ok = r.tool("set 13a2h 16 --rom --stop-mc --json");
  REQUIRE(ok.rc == 0);
  CHECK(ok.err == "lmcfg set: MC was stopped for the ROM write and started again\n");
  CHECK(r.valid("report-param.schema.json", ok.out));
  auto back = r.tool("get 0x13A2 --rom --json");
  CHECK(back.rc == 0);
  CHECK(back.out.find("\"raw\":16,\"raw_hex\":\"00000010\",\"integer\":16,") != std::string::npos);
  CHECK(slurp(r.dir / "drive.json").find("\"mc_running\": true") != std::string::npos);
}

TEST_CASE("seed003 §10 set --rom --yes in a script: stops MC, writes and starts it, as --stop-mc",
          "[cli][param]") {
  Rig r;
  auto ok = r.tool("set 13A2 16 --rom --yes");
  REQUIRE(ok.rc == 0);
  // The undo record first (its path holds the time), then the MC note.
  CHECK(ok.err.rfind("undo: saved the target's previous values to " + (r.dir / "state").string() +
                         "/lmcfg/undo/",
                     0) == 0);
  CHECK(
      ok.err.find("; to put them back: lmcfg undo --port sim:" + (r.dir / "drive.json").string() +
                  " --id 0x11\nlmcfg set: MC was stopped for the ROM write and started again\n") !=
      std::string::npos);
  auto back = r.tool("get 0x13A2 --rom --json");
  CHECK(back.out.find("\"raw\":16,") != std::string::npos);
  CHECK(slurp(r.dir / "drive.json").find("\"mc_running\": true") != std::string::npos);
  // -y too; a RAM write with --yes asks nothing either.
  CHECK(r.tool("set 13A2 17 --rom -y").rc == 0);
  CHECK(r.tool("set 13A2 18 --yes").rc == 0);
  CHECK(r.tool("get 0x13A2 --rom --json").out.find("\"raw\":17,") != std::string::npos);
}

TEST_CASE("LinRS §10 a refusal with zeroed No-meaning fields is the drive's: exit 5, its reason",
          "[cli][param][refusal]") {
  Rig r;
  // The simulated drive fills the key and value of its refusals with zeros.
  std::string state = slurp(r.dir / "drive.json");
  const auto at = state.find('{');
  state.insert(at + 1, "\"options\": {\"refusal_fields\": \"zeros\"},");
  spit(r.dir / "drive.json", state);
  auto g = r.tool("get 9999 --rom");
  CHECK(g.rc == 5);
  CHECK(g.err ==
        "lmcfg get: drive 11h refused ID 11h parameter configuration (main 05h sub 00h), 2 data "
        "byte(s) for UPID 9999h: C8h parameter unknown UPID\n"
        "lmcfg get: after the refusal: drive state: 8 Operation Enabled (state var 08C2h), status "
        "word 4C37h; actual error: No Error\n");
}

TEST_CASE("get and info --json validate against their documented shapes", "[cli][param][schema]") {
  Rig r;
  auto g = r.tool("get 13A2 --json");
  REQUIRE(g.rc == 0);
  CHECK(g.out ==
        "{\"upid\":\"13A2\",\"name\":\"P Gain Position Controller Set A\",\"type\":\"UINT16\","
        "\"memory\":\"RAM\",\"raw\":10,\"raw_hex\":\"0000000A\",\"integer\":10,\"unit\":\"\","
        "\"value\":\"10\"}\n");
  CHECK(r.valid("report-param.schema.json", g.out));
  auto i = r.tool("info --json");
  REQUIRE(i.rc == 0);
  CHECK(i.out.find("\"state\":{\"main\":8,\"name\":\"Operation Enabled\"") != std::string::npos);
  CHECK(r.valid("report-info.schema.json", i.out));
  CHECK_FALSE(r.valid("report-info.schema.json", "{\"state\": 1}"));
}

}  // namespace tools_test_param_info_cli
