// lmcfg serve's [archive] push against real git: a bare repository made by
// `git init --bare` as the remote (and a path where none is yet), checked with
// `git rev-parse`; one push_failed per failure episode, push_recovered, the
// push metrics through promtool, and commits going on while the push fails.
#include <catch2/catch.hpp>
#include <mutex>
#include <nlohmann/json.hpp>
#include <thread>

#include "files.hpp"
#include "promtool.hpp"
#include "serve_rig.hpp"

// This file's own namespace: the test binary is a unity build (tests/CMakeLists.txt).
namespace serve_test_serve_push {

using namespace lmcfg;
namespace fs = std::filesystem;
using namespace std::chrono_literals;

namespace {

// `git ARGS` run in `dir`; its stdout without the trailing newline, "" on failure.
std::string git(const fs::path& dir, const std::string& args) {
  const std::string cmd =
      "cd '" + dir.string() + "' && git " + args + " > git.txt 2>/dev/null || : > git.txt";
  if (std::system(cmd.c_str()) != 0) return "";
  std::string out = test::slurp(dir / "git.txt");
  while (!out.empty() && out.back() == '\n') out.pop_back();
  return out;
}

// The commissioned axis at MACID 0x11 with UPID 0010h at `value`.
void write_axis(const fs::path& path, int value) {
  auto j = nlohmann::json::parse(
      test::slurp(std::string(LMCFG_SOURCE_DIR) + "/tests/fixtures/sim/commissioned-axis.json"));
  for (auto& p : j["parameters"])
    if (p["upid"] == "0010") p["rom"] = p["ram"] = value;
  test::spit(path, j.dump(1));
}

// The service over one simulated axis, press/a, pushing to `remote`.
struct PushRig : test::ServiceRig {
  explicit PushRig(const std::string& remote) : ServiceRig("serve-push") {
    write_axis(dir.path / "a.json", 5);
    test::spit(dir.path / "plant.toml", "[archive]\npush = \"" + remote +
                                            "\"\n[schedule]\nbackup_every = \"1h\"\n"
                                            "[[line]]\nname = \"l1\"\nport = \"sim:" +
                                            (dir.path / "a.json").string() +
                                            "\"\n[[line.drive]]\nname = \"press/a\"\nid = 0x11\n");
    start(test::slurp(dir.path / "plant.toml"), [&](serve::ServiceOptions& o) {
      CHECK(o.inventory.archive.push == remote);
      o.push_retry_first = 20ms;
      o.push_retry_max = 80ms;
    });
  }
  std::vector<std::string> event_names() {
    std::lock_guard<std::mutex> lock(mu);
    std::vector<std::string> names;
    for (const auto& e : events) names.push_back(e["event"]);
    return names;
  }
  // Waits (bounded, 10 s) until /metrics contains `line`.
  bool metrics_show(const std::string& line) {
    for (int i = 0; i < 500; ++i) {
      if (service->metrics().find(line + "\n") != std::string::npos) return true;
      std::this_thread::sleep_for(20ms);
    }
    return false;
  }
  std::string head() { return git(dir.path / "archive", "rev-parse HEAD"); }
};

}  // namespace

TEST_CASE("serve push: every commit reaches a bare repository, no failure metrics",
          "[serve][push]") {
  test::ScratchDir remote("serve-remote");
  REQUIRE(std::system(("git init -q --bare '" + remote.path.string() + "/central.git'").c_str()) ==
          0);
  PushRig rig((remote.path / "central.git").string());
  rig.at(rig.now);  // the first backup: a commit, then its push
  REQUIRE(rig.metrics_show("lmcfg_archive_push_pending 0"));
  const std::string first = rig.head();
  REQUIRE(first.size() == 40);
  CHECK(git(remote.path, "--git-dir=central.git rev-parse HEAD") == first);

  write_axis(rig.dir.path / "a.json", 9);
  rig.at(rig.now + 1h);
  REQUIRE(rig.head() != first);
  REQUIRE(rig.metrics_show("lmcfg_archive_push_pending 0"));
  CHECK(git(remote.path, "--git-dir=central.git rev-parse HEAD") == rig.head());
  const std::string m = rig.service->metrics();
  CHECK(m.find("lmcfg_archive_push_failures_total 0\n") != std::string::npos);
  CHECK(m.find("lmcfg_archive_push_last_success_timestamp_seconds 1800003600\n") !=
        std::string::npos);
  CHECK(rig.event_names() == std::vector<std::string>{"drift"});  // the backup's change only
  test::check_with_promtool(m, rig.dir.path);
}

TEST_CASE(
    "serve push: an unreachable remote is retried, notified once, never blocks commits, and "
    "recovers",
    "[serve][push]") {
  test::ScratchDir remote("serve-remote");
  const fs::path central = remote.path / "central.git";  // not there yet
  PushRig rig(central.string());
  rig.at(rig.now);
  const std::string first = rig.head();
  REQUIRE(first.size() == 40);  // committed although the push fails
  REQUIRE(rig.metrics_show("lmcfg_archive_push_pending 1"));
  // Several retries, one notification for the whole episode.
  for (int i = 0;
       i < 500 && rig.service->metrics().find("push_failures_total 3\n") == std::string::npos; ++i)
    std::this_thread::sleep_for(10ms);
  {
    std::lock_guard<std::mutex> lock(rig.mu);
    REQUIRE(rig.events.size() == 1);
    CHECK(rig.events[0]["event"] == "push_failed");
    CHECK(rig.events[0]["remote"] == central.string());
    CHECK(rig.events[0]["time"] == "2027-01-15T08:00:00Z");
    CHECK(rig.events[0]["reason"].get<std::string>().rfind(
              "archive " + (rig.dir.path / "archive").string() + ": push to " + central.string(),
              0) == 0);
  }
  std::string m = rig.service->metrics();
  CHECK(m.find("lmcfg_archive_push_pending 1\n") != std::string::npos);
  CHECK(m.find("\nlmcfg_archive_push_last_success_timestamp_seconds ") == std::string::npos);
  test::check_with_promtool(m, rig.dir.path);

  // Backups and commits go on while the push fails.
  write_axis(rig.dir.path / "a.json", 9);
  rig.at(rig.now + 1h);
  const std::string second = rig.head();
  CHECK(second != first);
  CHECK(rig.event_names() == std::vector<std::string>{"push_failed", "drift"});

  // The remote appears: the next retry pushes both commits and says so once.
  REQUIRE(std::system(("git init -q --bare '" + central.string() + "'").c_str()) == 0);
  REQUIRE(rig.metrics_show("lmcfg_archive_push_pending 0"));
  CHECK(git(remote.path, "--git-dir=central.git rev-parse HEAD") == second);
  CHECK(git(remote.path, "--git-dir=central.git rev-parse HEAD~1") == first);
  CHECK(rig.event_names() == std::vector<std::string>{"push_failed", "drift", "push_recovered"});
  m = rig.service->metrics();
  CHECK(m.find("lmcfg_archive_push_last_success_timestamp_seconds 1800003600\n") !=
        std::string::npos);
}

TEST_CASE("serve push: commits an earlier run could not push go at the next start",
          "[serve][push]") {
  test::ScratchDir remote("serve-remote");
  const fs::path central = remote.path / "central.git";
  std::string committed;
  {
    PushRig rig(central.string());  // no remote yet: the push fails
    rig.at(rig.now);
    committed = rig.head();
    REQUIRE(committed.size() == 40);
    REQUIRE(rig.metrics_show("lmcfg_archive_push_pending 1"));
    // The service stops with the commit not pushed; the next start is over
    // the same archive.
    rig.service.reset();
    REQUIRE(std::system(("git init -q --bare '" + central.string() + "'").c_str()) == 0);
    rig.start(test::slurp(rig.dir.path / "plant.toml"), [](serve::ServiceOptions& o) {
      o.push_retry_first = 20ms;
      o.push_retry_max = 80ms;
    });
    REQUIRE(rig.metrics_show("lmcfg_archive_push_pending 0"));  // before any job ran
    CHECK(rig.service->job("1").error().code == Errc::not_found);
  }
  CHECK(git(remote.path, "--git-dir=central.git rev-parse HEAD") == committed);
}

TEST_CASE("serve push: [archive] keys are checked with their position",
          "[serve][push][inventory]") {
  const std::string line =
      "[[line]]\nname = \"l1\"\nport = \"sim:a.json\"\n"
      "[[line.drive]]\nname = \"a\"\nid = 0x11\n";
  auto inv =
      fleet::parse_inventory("[archive]\npush = \"\"\nmirror = \"x\"\n" + line, "plant.toml");
  REQUIRE_FALSE(inv.ok());
  CHECK(inv.error().message ==
        "plant.toml:3:1: unknown key 'mirror' in [archive] (known: push)\n"
        "plant.toml:2:8: 'push' must name a git remote (a remote's name, a URL or a path), not "
        "\"\"");
  inv = fleet::parse_inventory("archive = \"central\"\n" + line, "plant.toml");
  REQUIRE_FALSE(inv.ok());
  CHECK(inv.error().message == "plant.toml:1:11: 'archive' must be a table ([archive])");
  inv = fleet::parse_inventory("[archive]\npush = 3\n" + line, "plant.toml");
  REQUIRE_FALSE(inv.ok());
  CHECK(inv.error().message == "plant.toml:2:8: 'push' must be a string");
  inv = fleet::parse_inventory(line, "plant.toml");
  REQUIRE(inv.ok());
  CHECK(inv->archive.push.empty());
}

TEST_CASE("serve push: the Debian package's example inventory loads, and with its push set",
          "[serve][push][inventory]") {
  const std::string text =
      test::slurp(std::string(LMCFG_SOURCE_DIR) + "/packaging/plant.example.toml");
  REQUIRE_FALSE(text.empty());
  auto inv = fleet::parse_inventory(text, "plant.toml");
  REQUIRE(inv.ok());
  CHECK(inv->schedule.backup_every == std::chrono::hours(6));
  CHECK(inv->drive_count() == 2);
  CHECK(inv->archive.push.empty());  // commented out: no central remote by default
  std::string with_push = text;
  const std::string commented = "# push = ";
  with_push.replace(with_push.find(commented), commented.size(), "push = ");
  inv = fleet::parse_inventory(with_push, "plant.toml");
  REQUIRE(inv.ok());
  CHECK(inv->archive.push == "ssh://git@central.example/plant/site1.git");
}

}  // namespace serve_test_serve_push
