// Approved configurations in the archive (lib/fleet/approved.cpp,
// docs/fleet.md "Approved configurations") against a real git: the ref and
// its tag as git reads them, the refusals, commissioning and adoption.
#include <catch2/catch.hpp>
#include <filesystem>

#include "files.hpp"
#include "fleet/approved.hpp"
#include "fleet/archive.hpp"
#include "git_repo.hpp"
#include "subprocess.hpp"

// This file's own namespace: the test binary is a unity build (tests/CMakeLists.txt).
namespace fleet_test_approved {

using namespace lmcfg;
namespace fs = std::filesystem;

namespace {

struct Repo {
  test::ScratchDir d{"approved"};
  fleet::Archive archive = open();
  fleet::Archive open() {
    auto a = fleet::Archive::open((d.path / "arch").string(), true);
    REQUIRE(a.ok());
    test::set_git_identity(d.path / "arch");
    return std::move(a).value();
  }
  std::string commit(const std::string& path, const std::string& text) {
    fs::create_directories((d.path / "arch" / path).parent_path());
    test::spit(d.path / "arch" / path, text);
    auto c = archive.commit({path}, "backup " + path + "\n");
    REQUIRE(c.ok());
    REQUIRE(*c);
    return (*c)->id;
  }
};

std::string git(const fs::path& dir, const std::string& args) {
  return test::shell_output("git -C '" + dir.string() + "' " + args);
}

fleet::DriveEntry position(const std::string& name) {
  fleet::DriveEntry d;
  d.name = name;
  return d;
}

}  // namespace

TEST_CASE("approved: an approval is an annotated tag git reads, with who, when and why",
          "[fleet][approved]") {
  Repo r;
  const auto z = position("press3/z");
  const std::string first = r.commit("press3/z.json", "{\"a\": 1}\n");
  const std::string second = r.commit("press3/z.json", "{\"a\": 2}\n");
  CHECK(fleet::read_approval(r.archive, z).value() == std::nullopt);
  CHECK(fleet::approved_rev(r.archive, z).value() == "HEAD");
  CHECK(fleet::approval_json(std::nullopt).is_null());

  fleet::ApproveRequest req;
  req.rev = "HEAD~1";
  req.who = "maria";
  req.reason = "commissioned tuning";
  req.ticket = "CHG-1";
  req.time = 1'800'000'000;
  auto a = fleet::approve(r.archive, z, req);
  REQUIRE(a.ok());
  CHECK(a->commit == first);  // the revision resolved before it is recorded
  auto back = fleet::read_approval(r.archive, z);
  REQUIRE(back.ok());
  REQUIRE(*back);
  CHECK((*back)->commit == first);
  CHECK((*back)->who == "maria");
  CHECK((*back)->reason == "commissioned tuning");
  CHECK((*back)->ticket == "CHG-1");
  CHECK((*back)->kind == "operator");
  CHECK((*back)->time == 1'800'000'000);
  CHECK(fleet::approved_rev(r.archive, z).value() == first);
  CHECK(fleet::approval_json(*back) == nlohmann::ordered_json{{"rev", first},
                                                              {"time", "2027-01-15T08:00:00Z"},
                                                              {"who", "maria"},
                                                              {"reason", "commissioned tuning"},
                                                              {"ticket", "CHG-1"},
                                                              {"kind", "operator"}});
  const auto dir = r.d.path / "arch";
  CHECK(git(dir, "cat-file -t refs/lmcfg/approved/press3/z") == "tag\n");
  CHECK(git(dir, "rev-parse 'refs/lmcfg/approved/press3/z^{commit}'") == first + "\n");
  const std::string tag = git(dir, "cat-file tag refs/lmcfg/approved/press3/z");
  CHECK(tag.find("tagger maria <lmcfg@localhost> 1800000000 +0000\n") != std::string::npos);
  CHECK(tag.find("\nlmcfg approve: press3/z <- press3/z.json at " + first.substr(0, 12) +
                 " (HEAD~1)\n\nKind: operator\nOperator: maria\nReason: commissioned "
                 "tuning\nTicket: CHG-1\n") != std::string::npos);
  // The branch is untouched: an approval is no commit.
  CHECK(r.archive.resolve("HEAD").value()->id == second);

  // A later approval replaces it.
  req.rev = second;
  req.ticket = "";
  REQUIRE(fleet::approve(r.archive, z, req).ok());
  CHECK(fleet::read_approval(r.archive, z).value()->commit == second);
  CHECK(fleet::read_approval(r.archive, z).value()->ticket.empty());
}

TEST_CASE("approved: who, reason, ticket and revision pass the text rules, nothing recorded",
          "[fleet][approved]") {
  Repo r;
  const auto z = position("press3/z");
  r.commit("press3/z.json", "{}\n");
  const auto refused = [&](fleet::ApproveRequest req, const std::string& message) {
    INFO(message);
    auto a = fleet::approve(r.archive, z, req);
    REQUIRE_FALSE(a.ok());
    CHECK(a.error().code == make_error_code(Errc::invalid_argument));
    CHECK(a.error().message == message);
  };
  fleet::ApproveRequest req;
  req.who = "maria";
  req.reason = "spare accepted";
  fleet::ApproveRequest bad = req;
  bad.reason = "ok\nOperator: mallory";
  refused(bad,
          "reason contains a control character (0x0A at offset 2): give one line without "
          "control characters");
  bad.reason = std::string(3000, 'r');
  refused(bad, "reason is 3000 bytes long, at most 200 are accepted: shorten it");
  bad = req;
  bad.ticket = "T\x1B";
  refused(bad,
          "ticket contains a control character (0x1B at offset 1): give one line without "
          "control characters");
  bad = req;
  bad.who = "maria\r";
  refused(bad,
          "who contains a control character (0x0D at offset 5): give one line without "
          "control characters");
  bad = req;
  bad.rev = "HEAD\n";
  refused(bad,
          "rev contains a control character (0x0A at offset 4): give one line without "
          "control characters");
  CHECK(fleet::read_approval(r.archive, z).value() == std::nullopt);
  CHECK(fleet::approve(r.archive, z, req).ok());
}

TEST_CASE("approved: no reason, an unknown revision, a revision without the file: refused",
          "[fleet][approved]") {
  Repo r;
  const auto z = position("press3/z");
  fleet::ApproveRequest req;
  req.who = "maria";
  auto none = fleet::approve(r.archive, z, req);
  REQUIRE_FALSE(none.ok());
  CHECK(none.error().code == make_error_code(Errc::invalid_argument));
  CHECK(none.error().message ==
        "approving press3/z needs a reason (why this configuration is the one the position "
        "should hold); nothing recorded");
  req.reason = "r";
  auto empty = fleet::approve(r.archive, z, req);
  REQUIRE_FALSE(empty.ok());
  CHECK(empty.error().code == make_error_code(Errc::not_found));
  CHECK(empty.error().message == "archive " + r.archive.dir() + " has no commit yet");

  const std::string other = r.commit("press4/x.json", "{}\n");
  auto missing = fleet::approve(r.archive, z, req);
  REQUIRE_FALSE(missing.ok());
  CHECK(missing.error().code == make_error_code(Errc::not_found));
  CHECK(missing.error().message == "archive " + r.archive.dir() +
                                       " has no press3/z.json at HEAD (" + other.substr(0, 12) +
                                       "): nothing to approve; nothing recorded");
  req.rev = "nope";
  auto unknown = fleet::approve(r.archive, z, req);
  REQUIRE_FALSE(unknown.ok());
  CHECK(unknown.error().code == make_error_code(Errc::not_found));
  CHECK(unknown.error().message.rfind("archive " + r.archive.dir() + ": revision 'nope': ", 0) ==
        0);
  CHECK(fleet::read_approval(r.archive, z).value() == std::nullopt);
}

TEST_CASE(
    "approved: a backup commissions new positions at its commit and adopts the file of a "
    "position archived before approvals",
    "[fleet][approved]") {
  Repo r;
  const auto old_pos = position("press3/z");
  const auto new_pos = position("press3/x");
  const auto unread = position("press3/y");
  const std::string before = r.commit("press3/z.json", "{\"a\": 1}\n");
  fs::create_directories(r.d.path / "arch/press3");
  test::spit(r.d.path / "arch/press3/z.json", "{\"a\": 2}\n");
  test::spit(r.d.path / "arch/press3/x.json", "{\"b\": 1}\n");
  auto c = r.archive.commit({"press3/z.json", "press3/x.json"}, "backup\n");
  REQUIRE(c.ok());
  const std::string after = (*c)->id;
  auto made = fleet::commission(r.archive, {&old_pos, &new_pos, &unread}, before, after,
                                "lmcfg fleet", 1'800'000'000);
  REQUIRE(made.ok());
  REQUIRE(made->size() == 2);  // press3/y has no file: it waits for its first backup
  auto z = fleet::read_approval(r.archive, old_pos).value();
  REQUIRE(z);
  CHECK(z->commit == before);
  CHECK(z->kind == "adopted");
  CHECK(z->reason ==
        "the file the archive held when approvals began (no approval recorded before)");
  auto x = fleet::read_approval(r.archive, new_pos).value();
  REQUIRE(x);
  CHECK(x->commit == after);
  CHECK(x->kind == "commissioning");
  CHECK(x->who == "lmcfg fleet");
  CHECK(x->reason == "commissioning: the position's first backup");
  CHECK(fleet::read_approval(r.archive, unread).value() == std::nullopt);

  // Approved positions are left as they are.
  auto again = fleet::commission(r.archive, {&old_pos, &new_pos}, after, after, "x", 0);
  REQUIRE(again.ok());
  CHECK(again->empty());
  CHECK(fleet::read_approval(r.archive, old_pos).value()->commit == before);
}

TEST_CASE("approved: a position name git does not allow as a ref is named", "[fleet][approved]") {
  Repo r;
  const auto bad = position("press3/z.lock");
  r.commit("press3/z.lock.json", "{}\n");
  fleet::ApproveRequest req;
  req.reason = "r";
  auto a = fleet::approve(r.archive, bad, req);
  REQUIRE_FALSE(a.ok());
  CHECK(a.error().message == "archive " + r.archive.dir() +
                                 ": refs/lmcfg/approved/press3/z.lock is not a name git allows "
                                 "for a reference");
}

}  // namespace fleet_test_approved
