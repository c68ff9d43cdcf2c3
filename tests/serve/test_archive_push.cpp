// [archive] push's thread (lib/serve/archive_push.cpp): commits asked for are
// pushed to a bare repository made by `git init --bare`; a failing remote
// gives one push_failed per failure episode, retries with a growing wait, and
// a stop ends the thread at once even between retries.
#include <catch2/catch.hpp>
#include <mutex>
#include <thread>

#include "files.hpp"
#include "serve/archive_push.hpp"

// This file's own namespace: the test binary is a unity build (tests/CMakeLists.txt).
namespace serve_test_archive_push {

using namespace lmcfg;
using namespace lmcfg::serve;
using namespace lmcfg::serve::detail;
using namespace std::chrono_literals;
namespace fs = std::filesystem;

namespace {

struct Rig {
  test::ScratchDir dir{"archive-push"};
  std::mutex mu;
  std::vector<std::string> events, logged;
  Result<fleet::Archive> archive = fleet::Archive::open((dir.path / "archive").string(), true);

  // One commit more in the archive.
  void commit(const std::string& text) {
    test::spit(dir.path / "archive" / "a.txt", text);
    REQUIRE(archive.ok());
    auto made = archive->commit({"a.txt"}, "a: " + text);
    REQUIRE(made.ok());
  }
  Pusher::Options options(const std::string& remote) {
    Pusher::Options o;
    o.archive = (dir.path / "archive").string();
    o.remote = remote;
    o.retry_first = 20ms;
    o.retry_max = 40ms;
    o.clock = [] { return TimePoint(std::chrono::seconds(1'800'000'000)); };
    o.log = [this](const std::string& s) {
      std::lock_guard<std::mutex> lock(mu);
      logged.push_back(s);
    };
    o.emit = [this](const std::string& event, Json) {
      std::lock_guard<std::mutex> lock(mu);
      events.push_back(event);
    };
    return o;
  }
  std::vector<std::string> event_names() {
    std::lock_guard<std::mutex> lock(mu);
    return events;
  }
};

// `git rev-parse REF` in the bare repository `repo` ("" when it fails).
std::string rev_parse(const fs::path& repo, const std::string& ref) {
  const auto out = repo.parent_path() / "rev.txt";
  const std::string cmd = "git --git-dir='" + repo.string() + "' rev-parse " + ref + " > '" +
                          out.string() + "' 2>/dev/null || : > '" + out.string() + "'";
  if (std::system(cmd.c_str()) != 0) return "";
  std::string s = test::slurp(out);
  while (!s.empty() && s.back() == '\n') s.pop_back();
  return s;
}

template <class F>
bool eventually(F f) {
  for (int i = 0; i < 500; ++i) {
    if (f()) return true;
    std::this_thread::sleep_for(10ms);
  }
  return false;
}

}  // namespace

TEST_CASE("serve archive push: each commit asked for reaches the remote", "[serve][push]") {
  Rig rig;
  const fs::path remote = rig.dir.path / "central.git";
  REQUIRE(std::system(("git init -q --bare '" + remote.string() + "'").c_str()) == 0);
  rig.commit("one");
  Pusher pusher(rig.options(remote.string()));
  CHECK_FALSE(pusher.stats().pending);
  pusher.start(true);  // the commit of an "earlier run" goes with the first push
  auto head = [&] { return rig.archive->resolve("HEAD")->value().id; };
  REQUIRE(eventually([&] { return !pusher.stats().pending; }));
  CHECK(rev_parse(remote, "HEAD") == head());
  rig.commit("two");
  pusher.want();
  REQUIRE(eventually([&] { return rev_parse(remote, "HEAD") == head(); }));
  REQUIRE(eventually([&] { return !pusher.stats().pending; }));
  const auto stats = pusher.stats();
  CHECK(stats.failures == 0);
  CHECK(stats.last_success == TimePoint(std::chrono::seconds(1'800'000'000)));
  CHECK(rig.event_names().empty());
}

TEST_CASE("serve archive push: a failing remote is one push_failed, retried, and a stop ends it",
          "[serve][push]") {
  Rig rig;
  rig.commit("one");
  // A file where the remote's directory would be: every push fails.
  test::spit(rig.dir.path / "blocked", "not a directory");
  Pusher pusher(rig.options((rig.dir.path / "blocked" / "central.git").string()));
  pusher.start(false);
  CHECK_FALSE(pusher.stats().pending);  // nothing asked yet
  pusher.want();
  REQUIRE(eventually([&] { return pusher.stats().failures >= 3; }));
  const auto stats = pusher.stats();
  CHECK(stats.pending);
  CHECK_FALSE(stats.last_success);
  CHECK(rig.event_names() == std::vector<std::string>{"push_failed"});
  const auto t0 = std::chrono::steady_clock::now();
  pusher.stop();
  CHECK(std::chrono::steady_clock::now() - t0 < 2s);
}

}  // namespace serve_test_archive_push
