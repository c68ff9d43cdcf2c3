// The first thing a new user types: `lmcfg` alone, `lmcfg help`, `lmcfg help
// SUBCOMMAND` (tools/lmcfg/main.cpp; README "The commands", docs/cli.md).
#include <catch2/catch.hpp>
#include <sstream>

#include "files.hpp"
#include "subprocess.hpp"

// This file's own namespace: the test binary is a unity build (tests/CMakeLists.txt).
namespace tools_test_cli_help {

using namespace lmcfg;

namespace {

struct TempDir : test::ScratchDir {
  TempDir() : ScratchDir("help") {}
};

// The subcommand lines of the overview: the lines after "Subcommands:" up to
// the first empty one.
std::vector<std::string> subcommand_lines(const std::string& text) {
  std::istringstream in(text);
  std::vector<std::string> lines;
  std::string line;
  bool on = false;
  while (std::getline(in, line)) {
    if (line == "Subcommands:") {
      on = true;
    } else if (on && line.empty()) {
      break;
    } else if (on) {
      lines.push_back(line);
    }
  }
  return lines;
}

const std::vector<std::string> kNames = {
    "backup", "diff", "report",  "restore", "default", "undo", "journal", "get",   "set",
    "db",     "info", "convert", "scan",    "link",    "sim",  "fleet",   "serve", "ui"};

}  // namespace

TEST_CASE("first ten minutes: lmcfg alone lists every subcommand and what to try, exit 2",
          "[cli][help]") {
  TempDir d;
  auto r = test::run_tool_in(d.path, "");
  CHECK(r.exit_code == 2);
  CHECK(r.out.empty());
  CHECK(r.err.rfind("lmcfg: back up, diff, default and restore LinMot drive configurations over "
                    "LinRS\n\nUsage: lmcfg SUBCOMMAND [OPTIONS]\n",
                    0) == 0);
  CHECK(r.err.find("A subcommand is required") == std::string::npos);
  const auto lines = subcommand_lines(r.err);
  REQUIRE(lines.size() == kNames.size());
  for (std::size_t i = 0; i < kNames.size(); ++i) {
    INFO(lines[i]);
    CHECK(lines[i].rfind("  " + kNames[i] + " ", 0) == 0);
    CHECK(lines[i].size() > 14);  // the name, then its one-line description
  }
  CHECK(lines[0] == "  backup    Read a drive's configuration and write it to a JSON or XML file");
  CHECK(r.err.find("\nFirst commands to try, on a drive at its factory link (README \"Your first "
                   "real drive\"):\n  lmcfg scan --port /dev/ttyUSB0\n") != std::string::npos);
  CHECK(r.err.find("\n  lmcfg backup --port /dev/ttyUSB0 --baud 57600 --id 0x11 -o axis.json\n") !=
        std::string::npos);
}

TEST_CASE("first ten minutes: lmcfg help prints the same overview on stdout, exit 0",
          "[cli][help]") {
  TempDir d;
  auto alone = test::run_tool_in(d.path, "");
  auto help = test::run_tool_in(d.path, "help");
  CHECK(help.exit_code == 0);
  CHECK(help.err.empty());
  CHECK(help.out == alone.err);
}

TEST_CASE("first ten minutes: lmcfg help SUBCOMMAND equals lmcfg SUBCOMMAND --help",
          "[cli][help]") {
  TempDir d;
  std::vector<std::string> commands = kNames;
  commands.insert(commands.end(), {"db show", "fleet backup", "serve token add"});
  for (const auto& c : commands) {
    INFO(c);
    auto help = test::run_tool_in(d.path, "help " + c);
    auto flag = test::run_tool_in(d.path, c + " --help");
    CHECK(help.exit_code == 0);
    CHECK(flag.exit_code == 0);
    CHECK(help.out.find("Usage: ") != std::string::npos);
    CHECK(help.out == flag.out);
    CHECK(help.err == flag.err);
  }
}

TEST_CASE("first ten minutes: lmcfg help with an unknown subcommand names it, exit 2",
          "[cli][help]") {
  TempDir d;
  auto r = test::run_tool_in(d.path, "help bakup");
  CHECK(r.exit_code == 2);
  CHECK(r.err ==
        "lmcfg: unknown subcommand 'bakup' (one of: backup, diff, report, restore, default, undo, "
        "journal, get, set, db, info, convert, scan, link, sim, fleet, serve, ui; see lmcfg "
        "--help)\n");
}

}  // namespace tools_test_cli_help
