// The fleet archive (lib/fleet/archive.cpp, docs/fleet.md) against a real
// git: what it opens and refuses, commits only on change, reads files at a
// revision, a file's history, trailers as git reads them, stale locks.
#include <algorithm>
#include <catch2/catch.hpp>
#include <filesystem>

#include "files.hpp"
#include "fleet/archive.hpp"
#include "git_repo.hpp"
#include "subprocess.hpp"

// This file's own namespace: the test binary is a unity build (tests/CMakeLists.txt).
namespace fleet_test_archive {

using namespace lmcfg;
namespace fs = std::filesystem;

namespace {

fleet::Archive open_new(const fs::path& dir) {
  auto a = fleet::Archive::open(dir.string(), true);
  REQUIRE(a.ok());
  test::set_git_identity(dir);
  return std::move(a).value();
}

}  // namespace

TEST_CASE("archive: a new or empty directory becomes a repository, anything else is named",
          "[fleet][archive]") {
  test::ScratchDir d("archive-open");
  const auto fresh = d.path / "fresh";
  auto missing = fleet::Archive::open(fresh.string(), false);
  REQUIRE_FALSE(missing.ok());
  CHECK(missing.error().code == make_error_code(Errc::invalid_argument));
  CHECK(missing.error().message == "archive " + fresh.string() + " is not a git repository");
  REQUIRE(fleet::Archive::open(fresh.string(), true).ok());
  CHECK(fs::is_directory(fresh / ".git"));
  CHECK(fleet::Archive::open(fresh.string(), false).ok());

  const auto full = d.path / "full";
  fs::create_directories(full);
  test::spit(full / "notes.txt", "x");
  auto not_empty = fleet::Archive::open(full.string(), true);
  REQUIRE_FALSE(not_empty.ok());
  CHECK(not_empty.error().message ==
        "archive " + full.string() +
            " is not a git repository (and not empty, so it is not made one: give an empty or "
            "new directory, or run git init there)");

  auto file = fleet::Archive::open((full / "notes.txt").string(), true);
  REQUIRE_FALSE(file.ok());
  CHECK(file.error().message == "archive " + (full / "notes.txt").string() + " is not a directory");

  const auto bare = d.path / "bare.git";
  REQUIRE(std::system(("git init -q --bare '" + bare.string() + "'").c_str()) == 0);
  auto b = fleet::Archive::open(bare.string(), false);
  REQUIRE_FALSE(b.ok());
  CHECK(b.error().message == "archive " + bare.string() +
                                 " is a bare git repository; give a clone with a work tree "
                                 "(push to the bare one with --push)");
}

TEST_CASE("archive: a file read names the revision it cannot find, and a folder is not a file",
          "[fleet][archive]") {
  test::ScratchDir d("archive-read");
  const auto dir = d.path / "arch";
  auto a = open_new(dir);
  fs::create_directories(dir / "line2");
  test::spit(dir / "line2" / "a.json", "{}\n");
  REQUIRE(a.commit({"line2/a.json"}, "fleet backup: line2").ok());
  auto unknown_read = a.read("line2/a.json", "no-such-rev");
  REQUIRE_FALSE(unknown_read.ok());
  CHECK(unknown_read.error().code == make_error_code(Errc::not_found));
  CHECK(unknown_read.error().message.rfind("archive " + dir.string() + ": revision 'no-such-rev': ",
                                           0) == 0);
  CHECK(a.read("line2/a.json").value() == std::optional<std::string>("{}\n"));
  CHECK_FALSE(a.read("line2/b.json").value());
  auto folder = a.read("line2");
  REQUIRE_FALSE(folder.ok());
  CHECK(folder.error().message == "archive " + dir.string() + ": line2 at HEAD is not a file");
}

TEST_CASE("archive: commits only on change, reads any revision, git log agrees",
          "[fleet][archive]") {
  test::ScratchDir d("archive-commit");
  const auto dir = d.path / "arch";
  auto a = open_new(dir);
  CHECK(a.dir() == dir.string());
  // No commit yet: HEAD resolves to nothing, files read as absent.
  auto head = a.resolve("HEAD");
  REQUIRE(head.ok());
  CHECK_FALSE(*head);
  CHECK_FALSE(a.read("press3.json").value());
  CHECK(a.history("press3.json").value().empty());

  test::spit(dir / "press3.json", "{\"v\": 1}\n");
  auto first = a.commit({"press3.json"}, "fleet backup: 1 new\n\npress3: new");
  REQUIRE(first.ok());
  REQUIRE(*first);
  CHECK((*first)->summary == "fleet backup: 1 new");
  CHECK((*first)->message == "fleet backup: 1 new\n\npress3: new");
  CHECK((*first)->id.size() == 40);
  // The same content again: no commit.
  auto same = a.commit({"press3.json"}, "fleet backup: no changes");
  REQUIRE(same.ok());
  CHECK_FALSE(*same);
  // Unless it is a record.
  auto record =
      a.commit({}, "fleet restore: press3 <- press3.json at HEAD: restored and verified", true);
  REQUIRE(record.ok());
  REQUIRE(*record);
  test::spit(dir / "press3.json", "{\"v\": 2}\n");
  auto second = a.commit({"press3.json"}, "fleet backup: 1 changed");
  REQUIRE(second.ok());
  REQUIRE(*second);

  CHECK(a.read("press3.json").value() == std::optional<std::string>("{\"v\": 2}\n"));
  CHECK(a.read("press3.json", "HEAD~2").value() == std::optional<std::string>("{\"v\": 1}\n"));
  CHECK(a.read("press3.json", (*first)->id).value() == std::optional<std::string>("{\"v\": 1}\n"));
  CHECK_FALSE(a.read("other.json").value());
  CHECK(a.resolve("HEAD~1").value()->id == (*record)->id);
  auto unknown = a.resolve("no-such-rev");
  REQUIRE_FALSE(unknown.ok());
  CHECK(unknown.error().code == make_error_code(Errc::not_found));
  CHECK(unknown.error().message.rfind("archive " + dir.string() + ": revision 'no-such-rev': ",
                                      0) == 0);

  // The file's history: the commits that changed it, newest first; the
  // record only when asked for.
  auto h = a.history("press3.json");
  REQUIRE(h.ok());
  REQUIRE(h->size() == 2);
  CHECK((*h)[0].commit.id == (*second)->id);
  CHECK((*h)[1].commit.id == (*first)->id);
  CHECK((*h)[0].author == "Test Op <op@example.com>");
  CHECK((*h)[0].time > 0);
  auto with_records = a.history("press3.json", 100, [](const fleet::CommitInfo& c) {
    return c.summary.rfind("fleet restore: ", 0) == 0;
  });
  REQUIRE(with_records.ok());
  REQUIRE(with_records->size() == 3);
  CHECK((*with_records)[1].commit.id == (*record)->id);
  CHECK(a.history("press3.json", 1).value().size() == 1);
  // git itself sees the same three commits, newest first.
  CHECK(test::shell_output("git -C '" + dir.string() + "' log --format=%s") ==
        "fleet backup: 1 changed\n"
        "fleet restore: press3 <- press3.json at HEAD: restored and verified\n"
        "fleet backup: 1 new\n");
}

TEST_CASE("archive: trailers are the last paragraph when every line of it is Key: value",
          "[fleet][archive]") {
  using Pairs = std::vector<std::pair<std::string, std::string>>;
  CHECK(fleet::message_trailers("fleet restore: z <- z.json at HEAD\n\nbody\n\nOperator: ana\n"
                                "Reason: spindle swap\nTicket: T-17\n") ==
        Pairs{{"Operator", "ana"}, {"Reason", "spindle swap"}, {"Ticket", "T-17"}});
  CHECK(fleet::message_trailers("subject only").empty());
  CHECK(fleet::message_trailers("subject\n\nnot a trailer line\n").empty());
}

TEST_CASE("archive: stale lock files left by a killed process are removed, commits work again",
          "[fleet][archive]") {
  test::ScratchDir d("archive-locks");
  const auto dir = d.path / "arch";
  auto a = open_new(dir);
  test::spit(dir / "a.json", "1\n");
  REQUIRE(a.commit({"a.json"}, "first").value());
  const auto branch = test::shell_output("git -C '" + dir.string() + "' symbolic-ref --short HEAD");
  REQUIRE_FALSE(branch.empty());
  const std::string name = branch.substr(0, branch.size() - 1);
  test::spit(dir / ".git" / "index.lock", "");
  test::spit(dir / ".git" / "refs" / "heads" / (name + ".lock"), "");
  test::spit(dir / "a.json", "2\n");
  auto blocked = a.commit({"a.json"}, "second");
  CHECK_FALSE(blocked.ok());
  auto removed = a.remove_stale_locks();
  REQUIRE(removed.ok());
  std::sort(removed->begin(), removed->end());
  CHECK(*removed == std::vector<std::string>{"index.lock", "refs/heads/" + name + ".lock"});
  CHECK_FALSE(fs::exists(dir / ".git" / "index.lock"));
  auto second = a.commit({"a.json"}, "second");
  REQUIRE(second.ok());
  CHECK(*second);
  CHECK(a.remove_stale_locks().value().empty());
}

TEST_CASE("archive: a file is never written through a symbolic link or into .git",
          "[fleet][archive]") {
  test::ScratchDir d("archive-links");
  const auto dir = d.path / "archive";
  auto a = open_new(dir);
  fs::create_directories(d.path / "outside");
  fs::create_directory_symlink(d.path / "outside", dir / "press3");
  fs::create_symlink(d.path / "outside" / "x.json", dir / "x.json");

  auto through = a.work_path("press3/z.json");
  REQUIRE_FALSE(through.ok());
  CHECK(through.error().code == Errc::file_error);
  CHECK(through.error().message == "archive " + dir.string() + ": press3 is a symbolic link (to " +
                                       (d.path / "outside").string() +
                                       "); the archive writes no file through a link: replace "
                                       "it with a folder or remove it");
  CHECK(a.work_path("x.json").error().message ==
        "archive " + dir.string() + ": x.json is a symbolic link (to " +
            (d.path / "outside" / "x.json").string() +
            "); the archive writes no file through a link: replace it with a folder or remove it");
  CHECK(a.work_path("new/deeper/z.json").value() == (dir / "new/deeper/z.json").string());
  CHECK(a.work_path("new/.Git/z.json").error().message ==
        "archive " + dir.string() +
            ": will not write new/.Git/z.json (its '.Git' leaves the work tree or enters git's "
            "folder)");
  CHECK(fs::is_empty(d.path / "outside"));
}

TEST_CASE("archive: set_author's name is the author of the commits after it, git's before",
          "[fleet][archive]") {
  test::ScratchDir d("archive-author");
  auto a = open_new(d.path / "a");
  test::spit(d.path / "a" / "x.json", "1");
  REQUIRE(a.commit({"x.json"}, "first").value());
  a.set_author("lmcfg serve on plant-pc", "lmcfg-serve@plant-pc");
  test::spit(d.path / "a" / "x.json", "2");
  REQUIRE(a.commit({"x.json"}, "second").value());
  // Moved, the archive keeps it.
  fleet::Archive moved = std::move(a);
  test::spit(d.path / "a" / "x.json", "3");
  REQUIRE(moved.commit({"x.json"}, "third").value());
  auto h = moved.history("x.json");
  REQUIRE(h.ok());
  REQUIRE(h->size() == 3);
  CHECK((*h)[0].author == "lmcfg serve on plant-pc <lmcfg-serve@plant-pc>");
  CHECK((*h)[1].author == "lmcfg serve on plant-pc <lmcfg-serve@plant-pc>");
  CHECK((*h)[2].author == "Test Op <op@example.com>");
}

}  // namespace fleet_test_archive
