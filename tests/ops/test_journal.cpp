// The local audit journal (ops/journal.hpp): the record's fields, appending
// and reading back, a journal that cannot be written, and concurrent writers
// in two processes whose lines never interleave.
#include <sys/wait.h>
#include <unistd.h>

#include <catch2/catch.hpp>
#include <filesystem>
#include <nlohmann/json.hpp>
#include <set>
#include <sstream>

#include "files.hpp"
#include "ops/journal.hpp"

// This file's own namespace: the test binary is a unity build (tests/CMakeLists.txt).
namespace ops_test_journal {

using namespace lmcfg;
namespace fs = std::filesystem;

namespace {

ops::JournalEntry sample(const std::string& port, std::uint8_t id) {
  ops::JournalEntry e;
  e.time = "2026-11-24T20:30:00Z";
  e.audit = {"ana", "replaced the motor", "T-17"};
  e.command = "restore";
  e.port = port;
  e.macid = id;
  e.file = "axis.json";
  e.steps =
      nlohmann::ordered_json::array({{{"step", 1}, {"action", "stop_mc"}, {"text", "stop MC"}},
                                     {{"step", 2},
                                      {"action", "write_rom"},
                                      {"layer", "MC"},
                                      {"upid", "13A2"},
                                      {"name", "P Gain"},
                                      {"old", {{"raw", 40}, {"display", "40"}}},
                                      {"new", {{"raw", 1234}, {"display", "1234"}}}}});
  e.outcome = "restored and verified";
  e.exit_code = 0;
  e.exit_category = "ok";
  e.undo = "/state/lmcfg/undo/x.json";
  return e;
}

}  // namespace

TEST_CASE("journal: a record holds who, when, why, the drive, the steps and the outcome",
          "[journal]") {
  const auto j = ops::journal_record(sample("/dev/ttyUSB0", 0x11));
  CHECK(j.dump() ==
        R"({"time":"2026-11-24T20:30:00Z","who":"ana","reason":"replaced the motor",)"
        R"("ticket":"T-17","command":"restore","drive":{"port":"/dev/ttyUSB0","id":"11h"},)"
        R"("file":"axis.json","steps":[{"step":1,"action":"stop_mc","text":"stop MC"},)"
        R"({"step":2,"action":"write_rom","layer":"MC","upid":"13A2","name":"P Gain",)"
        R"("old":{"raw":40,"display":"40"},"new":{"raw":1234,"display":"1234"}}],)"
        R"("outcome":"restored and verified","exit_code":0,"exit_category":"ok","error":null,)"
        R"("undo":"/state/lmcfg/undo/x.json"})");
  // Without a reason, ticket, file or undo record those are null; a fleet
  // position is part of the drive; an empty time is now.
  ops::JournalEntry bare;
  bare.audit.who = "bob";
  bare.command = "set";
  bare.port = "sim:a.json";
  bare.macid = 0x2A;
  bare.position = "press3/z";
  const auto b = ops::journal_record(bare);
  CHECK(b["reason"].is_null());
  CHECK(b["ticket"].is_null());
  CHECK(b["file"].is_null());
  CHECK(b["undo"].is_null());
  CHECK(b["drive"] ==
        nlohmann::ordered_json{{"port", "sim:a.json"}, {"id", "2Ah"}, {"position", "press3/z"}});
  const std::string t = b["time"];
  CHECK(t.size() == 20);
  CHECK(t[4] == '-');
  CHECK(t[10] == 'T');
  CHECK(t.back() == 'Z');
}

TEST_CASE("journal: appended records read back in order, filtered by port and MACID", "[journal]") {
  test::ScratchDir d("journal");
  const auto path = d.path / "state" / "lmcfg" / "journal.jsonl";  // directories made
  REQUIRE(ops::append_journal(path, ops::journal_record(sample("/dev/ttyUSB0", 0x11))).ok());
  REQUIRE(ops::append_journal(path, ops::journal_record(sample("/dev/ttyUSB0", 0x12))).ok());
  REQUIRE(ops::append_journal(path, ops::journal_record(sample("/dev/ttyUSB1", 0x11))).ok());
  // One line per record, each ending in a newline; the file is private.
  const std::string text = test::slurp(path);
  CHECK(std::count(text.begin(), text.end(), '\n') == 3);
  CHECK(text.back() == '\n');
  CHECK((fs::status(path).permissions() & fs::perms::all) ==
        (fs::perms::owner_read | fs::perms::owner_write));

  auto all = ops::read_journal(path);
  REQUIRE(all.ok());
  REQUIRE(all->size() == 3);
  CHECK((*all)[1]["drive"]["id"] == "12h");
  auto port = ops::read_journal(path, "/dev/ttyUSB0");
  REQUIRE(port.ok());
  CHECK(port->size() == 2);
  auto one = ops::read_journal(path, "/dev/ttyUSB0", 0x12);
  REQUIRE(one.ok());
  REQUIRE(one->size() == 1);
  CHECK((*one)[0] == ops::journal_record(sample("/dev/ttyUSB0", 0x12)));

  // No journal yet: no records. A damaged line: its file and line number.
  CHECK(ops::read_journal(d.path / "none.jsonl").value().empty());
  test::spit(d.path / "bad.jsonl", "{\"time\":\"x\"}\n{\"time\": cut\n");
  auto bad = ops::read_journal(d.path / "bad.jsonl");
  REQUIRE_FALSE(bad.ok());
  CHECK(bad.error().message ==
        (d.path / "bad.jsonl").string() + ":2: not a JSON object (expected one record per line)");
}

TEST_CASE("journal: a journal that cannot be written is an error naming it and the OS error",
          "[journal]") {
  test::ScratchDir d("journal-bad");
  fs::create_directories(d.path / "journal.jsonl");  // a directory where the file belongs
  auto r = ops::append_journal(d.path / "journal.jsonl", nlohmann::ordered_json{{"a", 1}});
  REQUIRE_FALSE(r.ok());
  CHECK(r.error().code == make_error_code(Errc::file_error));
  CHECK(r.error().message ==
        "journal " + (d.path / "journal.jsonl").string() + ": cannot open: Is a directory");
}

TEST_CASE("journal: two processes appending at once leave whole lines, none lost", "[journal]") {
  test::ScratchDir d("journal-race");
  const auto path = d.path / "journal.jsonl";
  constexpr int kPerWriter = 300;
  // Records larger than a pipe buffer's atomic size (4096 bytes), so a
  // writer that wrote in pieces would show up as broken lines.
  const std::string filler(6000, 'x');
  std::vector<pid_t> children;
  for (int w = 0; w < 2; ++w) {
    const pid_t pid = ::fork();
    REQUIRE(pid >= 0);
    if (pid == 0) {
      int failed = 0;
      for (int i = 0; i < kPerWriter; ++i) {
        nlohmann::ordered_json rec{{"writer", w}, {"n", i}, {"reason", filler}};
        if (!ops::append_journal(path, rec).ok()) ++failed;
      }
      ::_exit(failed == 0 ? 0 : 1);
    }
    children.push_back(pid);
  }
  for (pid_t pid : children) {
    int status = 0;
    REQUIRE(::waitpid(pid, &status, 0) == pid);
    CHECK(WIFEXITED(status));
    CHECK(WEXITSTATUS(status) == 0);
  }
  std::istringstream in(test::slurp(path));
  std::string line;
  std::set<std::pair<int, int>> seen;
  std::size_t lines = 0;
  while (std::getline(in, line)) {
    ++lines;
    auto j = nlohmann::json::parse(line, nullptr, false);
    REQUIRE_FALSE(j.is_discarded());
    CHECK(j["reason"] == filler);
    seen.emplace(j["writer"].get<int>(), j["n"].get<int>());
  }
  CHECK(lines == 2 * kPerWriter);
  CHECK(seen.size() == 2 * kPerWriter);
}

}  // namespace ops_test_journal
