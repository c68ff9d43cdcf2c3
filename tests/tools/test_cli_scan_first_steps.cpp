// lmcfg scan against the simulated drive served on a real pseudo-terminal
// (`lmcfg sim`, which hears only a master at the drive's own baud rate), and
// the first steps: `lmcfg sim` alone, unknown subcommands and stray words,
// output paths checked before the drive is talked to, `backup -o -`.
#include <sys/wait.h>

#include <catch2/catch.hpp>
#include <chrono>
#include <filesystem>
#include <fstream>
#include <nlohmann/json.hpp>
#include <sstream>

#include "files.hpp"
#include "sim/state_file.hpp"
#include "subprocess.hpp"

// This file's own namespace: the test binary is a unity build (tests/CMakeLists.txt).
namespace tools_test_cli_scan_first_steps {

using namespace lmcfg;
using test::slurp;
namespace fs = std::filesystem;

namespace {

struct Run {
  int exit_code = -1;
  std::string out, err;
  double seconds = 0;
};

struct TempDir : test::ScratchDir {
  TempDir() : ScratchDir("scan") {}
};

Run tool(const fs::path& dir, const std::string& args) {
  const std::string cmd = "cd '" + dir.string() + "' && '" + std::string(LMCFG_TOOL_PATH) + "' " +
                          args + " >stdout.txt 2>stderr.txt </dev/null";
  const auto t0 = std::chrono::steady_clock::now();
  const int rc = std::system(cmd.c_str());
  Run r;
  r.seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
  r.exit_code = WIFEXITED(rc) ? WEXITSTATUS(rc) : -1;
  r.out = slurp(dir / "stdout.txt");
  r.err = slurp(dir / "stderr.txt");
  return r;
}

// The demo axis at MACID 2Ah, 115200 Bd, with `checksum` (state-file names).
fs::path axis_2a(const fs::path& dir, const std::string& mode = "none",
                 const std::string& coverage = "id_through_data") {
  auto st =
      sim::load_state(std::string(LMCFG_SOURCE_DIR) + "/tests/fixtures/sim/commissioned-axis.json");
  REQUIRE(st.ok());
  auto j = sim::to_json(*st);
  j["macid"] = "2A";
  j["link"]["baud"] = 115200;
  j["checksum"]["mode"] = mode;
  j["checksum"]["coverage"] = coverage;
  if (mode == "crc_kermit") j["checksum"]["crc_init"] = "0000";
  const fs::path p = dir / ("axis-" + mode + "-" + coverage + ".sim.json");
  std::ofstream(p) << j.dump(2);
  return p;
}

}  // namespace

TEST_CASE(
    "seed003 §3.2.1 §6.1.2 scan: drive at 115200 MACID 2Ah on a pty, found with and "
    "without --baud",
    "[cli][scan][pty]") {
  TempDir d;
  const auto state = axis_2a(d.path);
  test::Child sim({LMCFG_TOOL_PATH, "sim", "--state", state.string()});
  const std::string pty = sim.read_line();
  REQUIRE(pty.rfind("/dev/", 0) == 0);
  CHECK(sim.read_line() ==
        "link options: --port " + pty + " --baud 115200 --id 0x2A --checksum none");

  auto one = tool(d.path, "scan --port " + pty + " --baud 115200 --quiet");
  INFO(one.err);
  CHECK(one.exit_code == 0);
  CHECK(one.out ==
        "drive at MACID 0x2A (42), 115200 8N1, checksum none: --baud 115200 --id 0x2A "
        "--checksum none\n");
  WARN("scan of 256 MACIDs at 115200 over a pty: " << one.seconds << " s");

  auto all = tool(d.path, "scan --port " + pty + " --json");
  CHECK(all.exit_code == 0);
  auto j = nlohmann::json::parse(all.out);
  REQUIRE(j["found"].size() == 1);
  CHECK(j["found"][0]["id"] == 42);
  CHECK(j["found"][0]["options"] == "--baud 115200 --id 0x2A --checksum none");
  // Every §3.2.1 rate, factory 57600 first.
  REQUIRE(j["passes"].size() == 6);
  CHECK(j["passes"][0]["line"] == "57600 8N1");
  CHECK(j["passes"][1]["line"] == "115200 8N1");
  {  // the report's shape: schemas/report-scan.schema.json, checked by ajv
    std::ofstream(d.path / "scan.json") << all.out;
    const auto ajv = fs::path(LMCFG_SOURCE_DIR) / "tools/node/node_modules/.bin/ajv";
    const auto schema = fs::path(LMCFG_SOURCE_DIR) / "schemas/report-scan.schema.json";
    CHECK(std::system(("'" + ajv.string() + "' validate --spec=draft2020 --strict=true -s '" +
                       schema.string() + "' -d '" + (d.path / "scan.json").string() +
                       "' >/dev/null 2>&1")
                          .c_str()) == 0);
  }
  WARN("scan of every rate over a pty: " << all.seconds << " s");
}

TEST_CASE("seed003 §4.4 §15 scan detects the drive's checksum variant from its answers",
          "[cli][scan][pty]") {
  TempDir d;
  const auto state = axis_2a(d.path, "crc_kermit", "start_through_data");
  test::Child sim({LMCFG_TOOL_PATH, "sim", "--state", state.string()});
  const std::string pty = sim.read_line();
  REQUIRE(pty.rfind("/dev/", 0) == 0);
  auto r = tool(d.path, "scan --port " + pty + " --baud 115200 --quiet");
  INFO(r.err);
  CHECK(r.exit_code == 0);
  CHECK(r.out ==
        "drive at MACID 0x2A (42), 115200 8N1, checksum crc-kermit coverage=start: --baud "
        "115200 --id 0x2A --checksum crc-kermit --checksum-coverage start\n");
}

TEST_CASE("scan exits 1 when no drive answered", "[cli][scan]") {
  TempDir d;
  const auto state = axis_2a(d.path);
  fs::copy_file(state, d.path / "drive.json");
  auto r = tool(d.path, "scan --port sim:drive.json --baud 115200 --from 0x30 --to 0x3F --quiet");
  CHECK(r.exit_code == 1);
  CHECK(r.out.rfind("no drive answered (1 setting(s), MACIDs 0x30..0x3F", 0) == 0);
}

TEST_CASE("seed003 §4.4 every checksum variant and coverage works with the matching options",
          "[cli][checksum]") {
  TempDir d;
  const std::pair<const char*, const char*> modes[] = {
      {"add", "add"}, {"crc_ccitt", "crc-ffff"}, {"crc_kermit", "crc-kermit"}};
  const std::pair<const char*, const char*> coverages[] = {
      {"id_through_data", "id"}, {"start_through_data", "start"}, {"data_only", "data"}};
  for (const auto& [mode, option] : modes) {
    for (const auto& [coverage, cov_option] : coverages) {
      const auto state = axis_2a(d.path, mode, coverage);
      const std::string link = "--port sim:" + state.filename().string() +
                               " --id 0x2A --checksum " + option + " --checksum-coverage " +
                               cov_option;
      DYNAMIC_SECTION(link) {
        auto info = tool(d.path, "info " + link);
        INFO(info.err);
        CHECK(info.exit_code == 0);
        auto b = tool(d.path, "backup " + link + " -o out.json --quiet");
        INFO(b.err);
        CHECK(b.exit_code == 0);
        auto wrong = tool(d.path, "info --port sim:" + state.filename().string() +
                                      " --id 0x2A --timeout-ms 20 --retries 0");
        CHECK(wrong.exit_code == 4);
      }
    }
  }
}

TEST_CASE("seed003 §6.1.1.1 a non-factory default response layout: get, info, scan work",
          "[cli][layout]") {
  TempDir d;
  const auto state = axis_2a(d.path);
  auto j = nlohmann::json::parse(slurp(state));
  j["default_response"]["state_var"] = false;
  j["default_response"]["warn_word"] = true;
  j["default_response"]["monitoring_2"] = true;
  std::ofstream(d.path / "layout.json") << j.dump(2);
  const std::string link = "--port sim:layout.json --id 0x2A";
  auto info = tool(d.path, "info " + link);
  INFO(info.err);
  CHECK(info.exit_code == 0);
  auto get = tool(d.path, "get 0x13A2 " + link);
  INFO(get.err);
  CHECK(get.exit_code == 0);
  auto explicit_layout =
      tool(d.path, "get 0x13A2 " + link +
                       " --response-layout comm_state,status_word,warn_word,monitoring_1,"
                       "monitoring_2");
  CHECK(explicit_layout.exit_code == 0);
  CHECK(explicit_layout.out == get.out);
  auto factory = tool(d.path, "get 0x13A2 " + link + " --response-layout factory");
  CHECK(factory.exit_code == 4);
  auto scan = tool(d.path, "scan --port sim:layout.json --baud 115200 --quiet");
  CHECK(scan.exit_code == 0);
  CHECK(scan.out.find("--id 0x2A") != std::string::npos);
}

TEST_CASE("first steps: lmcfg sim alone serves the demo axis on a pty", "[cli][sim][pty]") {
  TempDir d;
  test::Child sim({LMCFG_TOOL_PATH, "sim"});
  const std::string pty = sim.read_line();
  REQUIRE(pty.rfind("/dev/", 0) == 0);
  const std::string options = sim.read_line();
  CHECK(options == "link options: --port " + pty + " --baud 57600 --id 0x11 --checksum none");
  auto r = tool(d.path, "info " + options.substr(std::string("link options: ").size()));
  INFO(r.err);
  CHECK(r.exit_code == 0);
}

TEST_CASE("first steps: unknown subcommands and stray words are errors naming them",
          "[cli][first-steps]") {
  TempDir d;
  auto fleet = tool(d.path, "fleat backup x");
  CHECK(fleet.exit_code == 2);
  CHECK(fleet.err ==
        "lmcfg: unknown subcommand 'fleat' (one of: backup, diff, report, restore, default, undo, "
        "journal, get, set, db, info, convert, scan, link, sim, fleet, serve, ui; see lmcfg "
        "--help)\n");
  auto stray = tool(d.path, "info stray --port sim:none.json");
  CHECK(stray.exit_code == 2);
  CHECK(stray.err == "lmcfg: unexpected argument 'stray' (see lmcfg SUBCOMMAND --help)\n");
}

TEST_CASE("first steps: backup checks its output path first and writes -o - to stdout",
          "[cli][first-steps]") {
  TempDir d;
  fs::copy_file(std::string(LMCFG_SOURCE_DIR) + "/tests/fixtures/sim/used-spare.json",
                d.path / "spare.json");
  auto missing = tool(d.path, "backup --port sim:spare.json -o no/such/dir/x.json --trace t.trace");
  CHECK(missing.exit_code == 2);
  CHECK(missing.err ==
        "lmcfg backup: -o 'no/such/dir/x.json': directory 'no/such/dir' does not exist; create "
        "it or name another path\n");
  CHECK_FALSE(fs::exists(d.path / "t.trace"));  // the link was never opened
  if (::geteuid() != 0) {
    fs::create_directories(d.path / "ro");
    fs::permissions(d.path / "ro", fs::perms::owner_read | fs::perms::owner_exec);
    auto ro = tool(d.path, "backup --port sim:spare.json -o ro/x.json");
    CHECK(ro.exit_code == 2);
    CHECK(ro.err ==
          "lmcfg backup: -o 'ro/x.json': directory 'ro' is not writable (Permission denied)\n");
  }
  auto out = tool(d.path, "backup --port sim:spare.json -o - --quiet");
  INFO(out.err);
  CHECK(out.exit_code == 0);
  CHECK_FALSE(fs::exists(d.path / "-"));
  auto j = nlohmann::json::parse(out.out);
  CHECK(j["format"] == "lmcfg-drive-config");
}

TEST_CASE("first steps: db scan checks its output path before talking to the drive",
          "[cli][first-steps]") {
  TempDir d;
  fs::copy_file(std::string(LMCFG_SOURCE_DIR) + "/tests/fixtures/sim/used-spare.json",
                d.path / "spare.json");
  auto missing = tool(
      d.path, "db scan --profile p1 --port sim:spare.json -o no/such/dir/s.tsv --trace t.trace");
  CHECK(missing.exit_code == 2);
  CHECK(missing.err ==
        "lmcfg db scan: -o 'no/such/dir/s.tsv': directory 'no/such/dir' does not exist; create "
        "it or name another path\n");
  CHECK_FALSE(fs::exists(d.path / "t.trace"));  // the link was never opened
}

// docs/reliability.md: a drive command that never got an answer names the likely
// wrong setting and what to run; the protocol detail only with --verbose.
// (Wrong parity: a pseudo-terminal cannot change parity, so that case is not
// tested here; the advice for answers no setting explains names --parity.)
TEST_CASE("errors that say what to do: wrong baud rate, MACID and checksum", "[cli][advice][pty]") {
  TempDir d;
  const auto state = axis_2a(d.path);  // 115200 Bd, MACID 2Ah, no checksum
  test::Child sim({LMCFG_TOOL_PATH, "sim", "--state", state.string()});
  const std::string pty = sim.read_line();
  REQUIRE(pty.rfind("/dev/", 0) == 0);
  const std::string fast = " --timeout-ms 20 --retries 0";

  SECTION("wrong baud rate") {
    auto r = tool(d.path, "info --port " + pty + " --baud 57600 --id 0x2A" + fast);
    CHECK(r.exit_code == 4);
    CHECK(r.err ==
          "lmcfg info: no answer from MACID 2Ah at 57600 Bd: check --id and --baud (and "
          "--parity), or run `lmcfg scan --port " +
              pty + "` to try every MACID and rate\n");
  }
  SECTION("wrong MACID") {
    auto r = tool(d.path, "get 13A2 --port " + pty + " --baud 115200 --id 0x11" + fast);
    CHECK(r.exit_code == 4);
    CHECK(r.err ==
          "lmcfg get: no answer from MACID 11h at 115200 Bd, but a drive answers as MACID 2Ah: "
          "try --id 0x2A\n");
  }
  SECTION("wrong checksum, with and without --verbose") {
    auto r = tool(d.path, "backup -o x.json --port " + pty + " --baud 115200 --id 0x2A" +
                              " --checksum crc" + fast + " --quiet");
    CHECK(r.exit_code == 4);
    CHECK(r.err ==
          "lmcfg backup: answers fail their checksum: the drive seems to use checksum none: try "
          "--checksum none\n");
    CHECK_FALSE(fs::exists(d.path / "x.json"));
    auto v = tool(d.path, "info --port " + pty + " --baud 115200 --id 0x2A --checksum crc" + fast +
                              " --verbose");
    CHECK(v.exit_code == 4);
    CHECK(v.err.rfind("lmcfg info: answers fail their checksum: the drive seems to use checksum "
                      "none: try --checksum none (detail: no valid answer from drive 2Ah",
                      0) == 0);
  }
}

TEST_CASE("errors that say what to do: a drive using CRC, asked without checksum",
          "[cli][advice][pty]") {
  TempDir d;
  const auto state = axis_2a(d.path, "crc_ccitt");
  test::Child sim({LMCFG_TOOL_PATH, "sim", "--state", state.string()});
  const std::string pty = sim.read_line();
  REQUIRE(pty.rfind("/dev/", 0) == 0);
  auto r = tool(d.path,
                "get 13A2 --port " + pty + " --baud 115200 --id 0x2A --timeout-ms 20 --retries 0");
  CHECK(r.exit_code == 4);
  CHECK(r.err ==
        "lmcfg get: answers fail their checksum: the drive seems to use checksum crc-ffff: try "
        "--checksum crc-ffff\n");
}

// docs/reliability.md: long operations have no upper bound in the manual (§10.4):
// --long-timeout-s sets the deadline, progress goes to stderr while waiting.
TEST_CASE("seed003 §10.4 a layer default taking 8 s: progress while waiting, --long-timeout-s",
          "[cli][long]") {
  TempDir d;
  auto j = nlohmann::json::parse(
      slurp(std::string(LMCFG_SOURCE_DIR) + "/tests/fixtures/sim/commissioned-axis.json"));
  j["timing_us"]["defaulting"] = 8'000'000;
  std::ofstream(d.path / "slow.json") << j.dump(2);
  const std::string link = " --port sim:slow.json";
  auto ok = tool(d.path, "default --layers mc --yes" + link);
  INFO(ok.err);
  CHECK(ok.exit_code == 0);
  CHECK(ok.err.find("lmcfg: still defaulting layer MC: 5 s (waiting up to 120 s; "
                    "--long-timeout-s)\n") != std::string::npos);
  auto quiet = tool(d.path, "default --layers mc --yes --quiet" + link);
  INFO(quiet.err);
  CHECK(quiet.exit_code == 0);
  CHECK(quiet.err.find("still defaulting") == std::string::npos);
  // A deadline shorter than the default: its answer never comes in time, the
  // drive is polled until it answers again and the layer read back
  // (docs/field.md "Slow saves").
  auto cut = tool(d.path, "default --layers mc --yes --long-timeout-s 3" + link);
  INFO(cut.err);
  CHECK(cut.exit_code == 0);
  CHECK(cut.err.find("note: default MC layer: the drive did not acknowledge defaulting layer MC "
                     "within 3 s and answered again 5 s later; the read-back confirmed it\n") !=
        std::string::npos);
  CHECK(cut.err.find("done: read back the MC layer (defaulted)\n") != std::string::npos);
  // Polled for less than the drive takes: exit 4, and how to wait longer.
  auto gone =
      tool(d.path, "default --layers mc --yes --long-timeout-s 3 --recover-timeout-s 2" + link);
  INFO(gone.err);
  CHECK(gone.exit_code == 4);
  CHECK(gone.err.find("lmcfg default: stopped at step 'default MC layer': no answer within 3 s, "
                      "and drive 11h did not answer again within 2 s after defaulting layer MC "
                      "(polled with §6 default response requests); the drive may still be busy "
                      "(real drives were silent for 30-90 s after saves and ROM writes) or gone: "
                      "if it is slow, wait longer with --long-timeout-s (now 3) or "
                      "--recover-timeout-s (now 2), else check its power and wiring. The drive is "
                      "partially defaulted (MC stopped): once the drive answers, run the same "
                      "command with longer waits") != std::string::npos);
  auto bad = tool(d.path, "default --layers mc --yes --long-timeout-s 9999" + link);
  CHECK(bad.exit_code == 2);
  CHECK(bad.err == "lmcfg default: --long-timeout-s 9999 is outside 1..3600\n");
}

}  // namespace tools_test_cli_scan_first_steps
