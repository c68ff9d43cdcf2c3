// A real `lmcfg serve` killed with SIGKILL in the middle of a backup run (a
// line of `lmcfg sim --tcp` drives answering after their modelled delays, so
// the run takes seconds), then started again: the archive passes
// `git fsck --full`, the work tree is clean, and the next run converges (every
// drive ok, one commit). Also the lock file a kill during a commit leaves.
#include <httplib.h>
#include <signal.h>
#include <sys/wait.h>

#include <algorithm>
#include <catch2/catch.hpp>
#include <nlohmann/json.hpp>
#include <thread>

#include "files.hpp"
#include "subprocess.hpp"

// This file's own namespace: the test binary is a unity build (tests/CMakeLists.txt).
namespace tools_test_serve_resilience {

using namespace lmcfg;
namespace fs = std::filesystem;
using namespace std::chrono_literals;

namespace {

// The exit status of `cmd` run in `dir`, its output in dir/cmd.txt.
int sh(const fs::path& dir, const std::string& cmd) {
  const int rc = std::system(("cd '" + dir.string() + "' && " + cmd + " > cmd.txt 2>&1").c_str());
  return WIFEXITED(rc) ? WEXITSTATUS(rc) : -1;
}

struct Plant {
  test::ScratchDir dir{"serve-kill"};
  std::unique_ptr<test::Child> sim;
  static constexpr int kDrives = 4;

  Plant() {
    // A line of four drives at their modelled speed (no --fast).
    std::vector<std::string> argv{LMCFG_TOOL_PATH, "sim", "--tcp", "127.0.0.1:0"};
    std::string drives;
    for (int i = 0; i < kDrives; ++i) {
      auto j = nlohmann::json::parse(test::slurp(std::string(LMCFG_SOURCE_DIR) +
                                                 "/tests/fixtures/sim/commissioned-axis.json"));
      j["macid"] = 0x11 + i;
      // MACID "By Parameter" (206Ch = 3, LinRS §15): 2076h holds the ID too,
      // or the drive would answer at the fixture's 11h after a reset.
      for (auto& param : j["parameters"])
        if (param["upid"] == "2076") param["rom"] = param["ram"] = 0x11 + i;
      const fs::path state = dir.path / ("d" + std::to_string(i) + ".json");
      test::spit(state, j.dump(1));
      argv.push_back("--state");
      argv.push_back(state.string());
      drives += "[[line.drive]]\nname = \"press/d" + std::to_string(i) +
                "\"\nid = " + std::to_string(0x11 + i) + "\n";
    }
    sim = std::make_unique<test::Child>(argv);
    const std::string port = sim->read_line();
    REQUIRE_FALSE(port.empty());
    test::spit(dir.path / "plant.toml",
               "[schedule]\nbackup_every = \"1d\"\n[[line]]\nname = \"l1\"\nport = "
               "\"tcp://127.0.0.1:" +
                   port + "\"\n" + drives);
  }

  std::unique_ptr<test::Child> serve() {
    return std::make_unique<test::Child>(std::vector<std::string>{
        LMCFG_TOOL_PATH, "serve", (dir.path / "plant.toml").string(), "--archive",
        (dir.path / "arch").string(), "--listen", "127.0.0.1:0", "--db", LMCFG_DB_PATH});
  }
};

// GET path on the service at `url` (http://127.0.0.1:PORT) as JSON; null when it fails.
nlohmann::json get(const std::string& url, const std::string& path) {
  httplib::Client c(url);
  auto res = c.Get(path);
  if (!res || res->status != 200) return nullptr;
  return nlohmann::json::parse(res->body);
}

// The first backup run of this start is done (its job number is not known to
// the test after a restart: numbers go on across restarts, docs/serve.md), so
// every position has a backup; bounded, 60 s. The positions' JSON.
nlohmann::json wait_backed_up(const std::string& url) {
  nlohmann::json drives;
  for (int i = 0; i < 600; ++i) {
    drives = get(url, "/api/v1/drives");
    const bool all = drives.is_array() && drives.size() == Plant::kDrives &&
                     std::all_of(drives.begin(), drives.end(), [](const nlohmann::json& d) {
                       return !d["last_backup"].is_null() && d["last_attempt"].is_object();
                     });
    if (all) break;
    std::this_thread::sleep_for(100ms);
  }
  return drives;
}

void check_converged(Plant& p, const std::string& url) {
  const auto drives = wait_backed_up(url);
  REQUIRE(drives.size() == Plant::kDrives);
  for (const auto& d : drives) {
    INFO(d.dump());
    CHECK(d["status"] == "ok");
    CHECK(d["last_attempt"]["result"] == "ok");
  }
  CHECK(sh(p.dir.path, "git -C arch fsck --full --strict") == 0);
  CHECK(sh(p.dir.path, "test -z \"$(git -C arch status --porcelain)\"") == 0);
  CHECK(sh(p.dir.path, "test $(git -C arch rev-list --count HEAD) = 1") == 0);
}

}  // namespace

TEST_CASE("serve cli: SIGKILL during a backup run leaves a sound archive, the restart converges",
          "[serve][cli][resilience]") {
  Plant p;
  auto serve = p.serve();
  std::string url = serve->read_line();
  REQUIRE(url.rfind("http://127.0.0.1:", 0) == 0);
  // The first scheduled backup starts at once: kill it after its first drive,
  // before its last (a drive takes a few hundred ms at the modelled speed).
  nlohmann::json job;
  for (int i = 0; i < 600; ++i) {
    job = get(url, "/api/v1/jobs/1");
    if (job.is_object() && job["done"].get<int>() >= 1) break;
    std::this_thread::sleep_for(20ms);
  }
  REQUIRE(job.is_object());
  REQUIRE(job["state"] == "running");
  REQUIRE(job["done"].get<int>() < Plant::kDrives);
  REQUIRE(::kill(serve->pid(), SIGKILL) == 0);
  serve.reset();  // reaps it
  // What the kill left: an archive git accepts (no commit yet), nothing staged.
  CHECK(sh(p.dir.path, "git -C arch fsck --full --strict") == 0);
  CHECK(sh(p.dir.path, "test -z \"$(git -C arch status --porcelain)\"") == 0);

  serve = p.serve();
  url = serve->read_line();
  REQUIRE_FALSE(url.empty());
  check_converged(p, url);
  CHECK(serve->stop() == 0);
}

TEST_CASE("serve cli: the index lock a kill during a commit leaves does not stop the next start",
          "[serve][cli][resilience]") {
  Plant p;
  REQUIRE(sh(p.dir.path, "git init -q arch") == 0);
  // libgit2 and git write the index through index.lock and a branch through
  // refs/heads/NAME.lock, renamed into place; a kill before the rename leaves them.
  test::spit(p.dir.path / "arch/.git/index.lock", "");
  fs::create_directories(p.dir.path / "arch/.git/refs/heads");
  test::spit(p.dir.path / "arch/.git/refs/heads/master.lock", "");
  test::spit(p.dir.path / "arch/.git/refs/heads/main.lock", "");
  auto serve = p.serve();
  const std::string url = serve->read_line();
  REQUIRE_FALSE(url.empty());
  check_converged(p, url);
  CHECK_FALSE(fs::exists(p.dir.path / "arch/.git/index.lock"));
  CHECK(serve->stop() == 0);
}

}  // namespace tools_test_serve_resilience
