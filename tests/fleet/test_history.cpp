// A position's history (lib/fleet/history.cpp, docs/fleet.md "History"): the
// commits that changed its file and the fleet restore records onto it, newest
// first, who and why from the trailers, as JSON and as text.
#include <catch2/catch.hpp>
#include <filesystem>

#include "files.hpp"
#include "fleet/archive.hpp"
#include "fleet/history.hpp"
#include "fleet/inventory.hpp"
#include "git_repo.hpp"

// This file's own namespace: the test binary is a unity build (tests/CMakeLists.txt).
namespace fleet_test_history {

using namespace lmcfg;
namespace fs = std::filesystem;

TEST_CASE("history: backups and restore records of one position, who and why from trailers",
          "[fleet][history]") {
  test::ScratchDir d("history");
  const auto dir = d.path / "arch";
  auto archive = fleet::Archive::open(dir.string(), true);
  REQUIRE(archive.ok());
  test::set_git_identity(dir);
  fs::create_directories(dir / "press3");
  test::spit(dir / "press3" / "z.json", "1\n");
  test::spit(dir / "press3" / "z-axis.json", "1\n");
  REQUIRE(archive->commit({"press3/z.json", "press3/z-axis.json"}, "fleet backup: 2 new").value());
  // A restore onto the neighbour whose name starts the same is not this one's.
  REQUIRE(
      archive
          ->commit({}, "fleet restore: press3/z-axis <- press3/z-axis.json at HEAD: restored", true)
          .value());
  REQUIRE(archive
              ->commit({},
                       "fleet restore: press3/z <- press3/z.json at HEAD: restored and verified\n\n"
                       "Operator: ana\nReason: spindle swap\nTicket: T-17\n",
                       true)
              .value());
  test::spit(dir / "press3" / "z.json", "2\n");
  REQUIRE(archive->commit({"press3/z.json"}, "fleet backup: 1 changed").value());

  fleet::DriveEntry z;
  z.name = "press3/z";
  auto events = fleet::position_history(*archive, z);
  REQUIRE(events.ok());
  REQUIRE(events->size() == 3);
  CHECK((*events)[0].kind == "backup");
  CHECK((*events)[0].who == "Test Op");  // no Operator: trailer: the author's name
  CHECK((*events)[0].reason.empty());
  CHECK((*events)[0].entry.commit.summary == "fleet backup: 1 changed");
  CHECK((*events)[1].kind == "restore");
  CHECK((*events)[1].who == "ana");
  CHECK((*events)[1].reason == "spindle swap");
  CHECK((*events)[1].ticket == "T-17");
  CHECK((*events)[2].kind == "backup");
  CHECK((*events)[2].entry.commit.summary == "fleet backup: 2 new");
  CHECK(fleet::position_history(*archive, z, 1).value().size() == 1);

  fleet::DriveEntry none;
  none.name = "press4/x";
  auto empty = fleet::position_history(*archive, none);
  REQUIRE(empty.ok());
  CHECK(empty->empty());
  CHECK(fleet::render_history(*empty, "press4/x") == "no history of press4/x in the archive\n");
}

TEST_CASE("history: the JSON the service returns and the text fleet log prints",
          "[fleet][history]") {
  fleet::PositionEvent restore;
  restore.entry.commit = {"0123456789abcdef0123456789abcdef01234567",
                          "fleet restore: z <- z.json at HEAD: restored and verified",
                          "fleet restore: z <- z.json at HEAD: restored and verified\n\n"
                          "Operator: ana\nReason: spindle swap\nTicket: T-17\n"};
  restore.entry.time = 1795552200;  // 2026-11-24 20:30:00 UTC
  restore.entry.author = "lmcfg fleet <lmcfg@localhost>";
  restore.kind = "restore";
  restore.who = "ana";
  restore.reason = "spindle swap";
  restore.ticket = "T-17";
  fleet::PositionEvent backup;
  backup.entry.commit = {"fedcba9876543210fedcba9876543210fedcba98", "fleet backup: 1 changed",
                         "fleet backup: 1 changed"};
  backup.entry.time = 1795552200 - 86400;
  backup.entry.author = "Test Op <op@example.com>";
  backup.kind = "backup";
  backup.who = "Test Op";
  const std::vector<fleet::PositionEvent> events{restore, backup};

  CHECK(fleet::render_history(events, "z") ==
        "2026-11-24T20:30:00Z  0123456789ab  restore  ana\n"
        "    fleet restore: z <- z.json at HEAD: restored and verified\n"
        "    why: spindle swap (ticket T-17)\n"
        "\n"
        "2026-11-23T20:30:00Z  fedcba987654  backup  Test Op\n"
        "    fleet backup: 1 changed\n");
  fleet::PositionEvent ticket_only = backup;
  ticket_only.ticket = "T-18";
  CHECK(fleet::render_history({ticket_only}, "z") ==
        "2026-11-23T20:30:00Z  fedcba987654  backup  Test Op\n"
        "    fleet backup: 1 changed\n"
        "    why: - (ticket T-18)\n");

  const auto j = fleet::history_json(events);
  REQUIRE(j.size() == 2);
  CHECK(j[0].dump() ==
        R"({"commit":"0123456789abcdef0123456789abcdef01234567","time":"2026-11-24T20:30:00Z",)"
        R"("kind":"restore","who":"ana","reason":"spindle swap","ticket":"T-17",)"
        R"("subject":"fleet restore: z <- z.json at HEAD: restored and verified",)"
        R"("author":"lmcfg fleet <lmcfg@localhost>",)"
        R"("message":"fleet restore: z <- z.json at HEAD: restored and verified\n\n)"
        R"(Operator: ana\nReason: spindle swap\nTicket: T-17\n"})");
  CHECK(j[1]["reason"].is_null());
  CHECK(j[1]["ticket"].is_null());
  CHECK(fleet::history_json({}).dump() == "[]");
}

TEST_CASE("history: a message or author that is not UTF-8 is shown escaped, never an error",
          "[fleet][history]") {
  test::ScratchDir d("history-bytes");
  const auto dir = d.path / "arch";
  auto archive = fleet::Archive::open(dir.string(), true);
  REQUIRE(archive.ok());
  test::set_git_identity(dir);
  test::spit(dir / "z.json", "1\n");
  // As `git commit` makes it by hand: bytes in Latin-1, not UTF-8.
  REQUIRE(archive->commit({"z.json"}, "fleet backup: caf\xE9\n\nOperator: Jos\xE9\n").value());
  fleet::DriveEntry z;
  z.name = "z";
  auto events = fleet::position_history(*archive, z);
  REQUIRE(events.ok());
  REQUIRE(events->size() == 1);
  CHECK((*events)[0].entry.commit.summary == "fleet backup: caf\\xE9");
  CHECK((*events)[0].who == "Jos\\xE9");
  // `lmcfg fleet log --json` writes this dump: it must not throw (type_error.316).
  const std::string text = fleet::history_json(*events).dump(2);
  const auto j = nlohmann::ordered_json::parse(text);
  CHECK(j[0]["subject"] == "fleet backup: caf\\xE9");
  CHECK(j[0]["message"] == "fleet backup: caf\\xE9\n\nOperator: Jos\\xE9\n");
}

TEST_CASE("history: the last backups' times come from the files at HEAD, not from a walk",
          "[fleet][history]") {
  test::ScratchDir d("history-times");
  const auto dir = d.path / "arch";
  auto archive = fleet::Archive::open(dir.string(), true);
  REQUIRE(archive.ok());
  test::set_git_identity(dir);
  fleet::DriveEntry a, b, c, e;
  a.name = "press3/a";
  b.name = "press3/b";
  c.name = "press3/c";  // never archived
  e.name = "press3/e";  // a file without a capture time
  CHECK(fleet::last_backup_times(*archive, {a, b}).value().empty());  // no commit yet
  auto file = [](const char* when) {
    return std::string(
               "{\n  \"format\": \"lmcfg-drive-config\",\n  \"identity\": {\n"
               "    \"captured_at\": \"") +
           when + "\"\n  }\n}\n";
  };
  fs::create_directories(dir / "press3");
  test::spit(dir / "press3" / "a.json", file("2026-11-24T20:30:00Z"));
  test::spit(dir / "press3" / "b.json", file("2026-11-24T20:30:01Z"));
  test::spit(dir / "press3" / "e.json", "{}\n");
  REQUIRE(
      archive->commit({"press3/a.json", "press3/b.json", "press3/e.json"}, "fleet backup: 3 new")
          .value());
  test::spit(dir / "press3" / "b.json", file("2026-11-25T06:00:00Z"));
  REQUIRE(archive->commit({"press3/b.json"}, "fleet backup: 1 changed").value());
  REQUIRE(archive->commit({}, "fleet restore: press3/b <- press3/b.json at HEAD: restored", true)
              .value());

  const auto times = fleet::last_backup_times(*archive, {a, b, c, e}).value();
  CHECK(times.size() == 2);
  CHECK(times.at("press3/a") == 1795552200);  // 2026-11-24T20:30:00Z
  CHECK(times.at("press3/b") == 1795586400);  // 2026-11-25T06:00:00Z
  CHECK(fleet::last_backup_times(*archive, {b}, "HEAD~2").value().at("press3/b") == 1795552201);
  // The same answer as the history walk gives for the commit that changed it.
  CHECK(fleet::iso_utc(times.at("press3/b")) == "2026-11-25T06:00:00Z");
}

}  // namespace fleet_test_history
