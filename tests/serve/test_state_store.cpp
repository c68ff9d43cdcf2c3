// The service's state store (lib/serve/state_store.cpp): each position's
// state written to states.json and read back at the next start (a position
// it does not name starts unknown), and the restores begun and not finished
// (pending/), one record per position, read back with their failures.
#include <catch2/catch.hpp>

#include "files.hpp"
#include "serve/state_store.hpp"

// This file's own namespace: the test binary is a unity build (tests/CMakeLists.txt).
namespace serve_test_state_store {

using namespace lmcfg;
using namespace lmcfg::serve;
using namespace lmcfg::serve::detail;

namespace {

fleet::Inventory plant() {
  auto inv = fleet::parse_inventory(
      "[[line]]\nname = \"l/1\"\nport = \"sim:a.json\"\n"
      "[[line.drive]]\nname = \"press/a\"\nid = 0x11\n"
      "[[line.drive]]\nname = \"press/b\"\nid = 0x12\n",
      "plant.toml");
  REQUIRE(inv.ok());
  return *inv;
}

struct Store {
  test::ScratchDir dir{"state-store"};
  std::vector<std::string> logged;
  fleet::Inventory inventory = plant();
  Result<fleet::Archive> archive = fleet::Archive::open((dir.path / "archive").string(), true);
  StateStore store{dir.path / "state", [this](const std::string& s) { logged.push_back(s); }};
};

}  // namespace

TEST_CASE("serve state store: the states outlive a restart through states.json",
          "[serve][states]") {
  Store s;
  REQUIRE(s.archive.ok());
  s.store.load(s.inventory, *s.archive);
  CHECK(s.store.state("press/a").status == "unknown");
  CHECK(s.store.state("press/a").message == "not read yet");
  s.store.with([](StateStore::Data& d) {
    auto& st = d.states["press/a"];
    st.status = "drift";
    st.message = "2 parameter(s) differ from the approved configuration";
    st.last_attempt = TimePoint(std::chrono::seconds(1'800'000'000));
    st.last_kind = "status";
    st.last_ok = true;
    st.differences = 2;
    st.differing = {"0010h changed", "0020h changed"};
    st.notified = "drift";
  });
  s.store.save();
  const auto file = nlohmann::json::parse(test::slurp(s.dir.path / "state" / "states.json"));
  CHECK(file["format"] == "lmcfg-serve-states");
  CHECK(file["drives"]["press/a"]["last_attempt"] == 1'800'000'000);

  StateStore again(s.dir.path / "state", [](const std::string&) {});
  again.load(s.inventory, *s.archive);
  const DriveState a = again.state("press/a");
  CHECK(a.status == "drift");
  CHECK(a.message == "2 parameter(s) differ from the approved configuration");
  CHECK(a.last_attempt == TimePoint(std::chrono::seconds(1'800'000'000)));
  CHECK(a.last_kind == "status");
  CHECK(a.differing == std::vector<std::string>{"0010h changed", "0020h changed"});
  CHECK(a.notified == "drift");
  CHECK_FALSE(a.last_backup);
  CHECK(again.state("press/b").status == "unknown");
  const auto counts = again.read([](const StateStore::Data& d) { return d.states.size(); });
  CHECK(counts == 2);
}

TEST_CASE("serve state store: a states.json of something else is logged, states start empty",
          "[serve][states]") {
  Store s;
  REQUIRE(s.archive.ok());
  std::filesystem::create_directories(s.dir.path / "state");
  test::spit(s.dir.path / "state" / "states.json", "[1, 2]");
  s.store.load(s.inventory, *s.archive);
  REQUIRE(s.logged.size() == 1);
  CHECK(s.logged[0] == "states: " + (s.dir.path / "state" / "states.json").string() +
                           " is not a states file of lmcfg serve; states start empty");
  CHECK(s.store.state("press/a").status == "unknown");
}

TEST_CASE("serve state store: an unfinished restore's record is kept until it is removed",
          "[serve][states]") {
  Store s;
  const auto& line = s.inventory.lines[0];
  PendingRestore p{"press/a",
                   "abc123",
                   "ops",
                   "tuning lost",
                   "T-1",
                   "",
                   true,
                   "4",
                   "untouched: nothing was written to it",
                   {},
                   0};
  p.failures.push_back({"2027-01-15T08:00:00Z", "5", "link: no answer"});
  p.failed_attempts = 1;
  REQUIRE(s.store.save_pending(line, line.drives[0], p).ok());
  CHECK(s.store.is_pending("press/a"));
  CHECK_FALSE(s.store.is_pending("press/b"));
  // '/' of the line's name is not a directory: "l_1-11h.json".
  CHECK(std::filesystem::exists(s.dir.path / "state" / "pending" / "l_1-11h.json"));

  StateStore again(s.dir.path / "state", [](const std::string&) {});
  CHECK(again.load_pending(s.inventory) == std::vector<std::string>{"press/a"});
  const auto back = again.pending("press/a");
  REQUIRE(back);
  CHECK(back->commit == "abc123");
  CHECK(back->who == "ops");
  CHECK(back->reason == "tuning lost");
  CHECK(back->ticket == "T-1");
  CHECK(back->skip_incompatible);
  CHECK(back->origin_job == "4");
  CHECK(back->drive_state == "untouched: nothing was written to it");
  REQUIRE(back->failures.size() == 1);
  CHECK(back->failures[0].job == "5");
  CHECK(back->failures[0].reason == "link: no answer");
  CHECK(back->failed_attempts == 1);

  again.remove_pending(line, line.drives[0]);
  CHECK_FALSE(again.is_pending("press/a"));
  CHECK_FALSE(std::filesystem::exists(s.dir.path / "state" / "pending" / "l_1-11h.json"));
}

TEST_CASE("serve state store: a record naming no drive of the inventory is left as it is",
          "[serve][states]") {
  Store s;
  std::filesystem::create_directories(s.dir.path / "state" / "pending");
  const auto stray = s.dir.path / "state" / "pending" / "old-20h.json";
  test::spit(stray, "{\"drive\": \"press/gone\", \"commit\": \"abc\"}");
  test::spit(s.dir.path / "state" / "pending" / "notes.txt", "not a record");
  CHECK(s.store.load_pending(s.inventory).empty());
  REQUIRE(s.logged.size() == 1);
  CHECK(s.logged[0] == "unfinished restore record " + stray.string() +
                           " names no drive of the inventory; left as it is");
  CHECK(std::filesystem::exists(stray));
}

}  // namespace serve_test_state_store
