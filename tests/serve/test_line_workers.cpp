// The service's line workers (lib/serve/line_workers.cpp): a line's tasks run
// in order on its own thread, lines run side by side, a task that never ends
// holds its line only (the queues' lock is free meanwhile), a stop drops what
// is queued, and the lines' numbers add up.
#include <atomic>
#include <catch2/catch.hpp>
#include <condition_variable>
#include <future>
#include <mutex>
#include <set>
#include <thread>

#include "serve/line_workers.hpp"

// This file's own namespace: the test binary is a unity build (tests/CMakeLists.txt).
namespace serve_test_line_workers {

using namespace lmcfg;
using namespace lmcfg::serve::detail;
using namespace std::chrono_literals;

namespace {

// A gate a task waits at until the test opens it.
struct Gate {
  std::mutex mu;
  std::condition_variable cv;
  bool open = false, reached = false;
  void wait() {
    std::unique_lock<std::mutex> lock(mu);
    reached = true;
    cv.notify_all();
    cv.wait(lock, [&] { return open; });
  }
  bool wait_reached(std::chrono::milliseconds d) {
    std::unique_lock<std::mutex> lock(mu);
    return cv.wait_for(lock, d, [&] { return reached; });
  }
  void release() {
    std::lock_guard<std::mutex> lock(mu);
    open = true;
    cv.notify_all();
  }
};

Task fn_task(std::function<void(bool)> fn) { return Task{nullptr, {}, std::move(fn)}; }

}  // namespace

TEST_CASE("serve line workers: a line's tasks run in order, on the line's own thread",
          "[serve][workers]") {
  LineWorkers lines(2);
  std::mutex mu;
  std::vector<std::string> ran;
  std::set<std::thread::id> threads[2];
  lines.start(
      [&](std::size_t line, Task& t) {
        std::lock_guard<std::mutex> lock(mu);
        ran.push_back(std::to_string(line) + ":" + t.only.at(0));
        threads[line].insert(std::this_thread::get_id());
      },
      {});
  for (const char* name : {"a", "b", "c"}) REQUIRE(lines.push(0, Task{nullptr, {name}, {}}));
  REQUIRE(lines.push(1, Task{nullptr, {"x"}, {}}));
  lines.wait_idle();
  std::vector<std::string> line0;
  for (const auto& r : ran)
    if (r[0] == '0') line0.push_back(r);
  CHECK(line0 == std::vector<std::string>{"0:a", "0:b", "0:c"});
  CHECK(ran.size() == 4);
  CHECK(threads[0].size() == 1);
  CHECK(threads[1].size() == 1);
  CHECK(*threads[0].begin() != *threads[1].begin());
}

TEST_CASE("serve line workers: a task that does not end holds its line and nothing else",
          "[serve][workers]") {
  LineWorkers lines(2);
  Gate hung;
  std::atomic<int> other{0};
  lines.start([&](std::size_t, Task& t) { t.fn(true); }, {});
  REQUIRE(lines.push(0, fn_task([&](bool) { hung.wait(); })));
  REQUIRE(hung.wait_reached(5s));
  // Line 0's worker is held: its queue takes tasks, line 1 runs its own, and
  // every call answers at once.
  const auto t0 = std::chrono::steady_clock::now();
  REQUIRE(lines.push(0, fn_task([&](bool) { ++other; })));
  CHECK(lines.queued(0, [](const Task&) { return true; }) == 1);
  REQUIRE(lines.push(1, fn_task([&](bool) { other += 10; })));
  for (int i = 0; i < 500 && other != 10; ++i) std::this_thread::sleep_for(10ms);
  CHECK(other == 10);
  lines.count(0, LineMetrics{5, 1, 0, 0, 1, 0.5, 0.5});
  CHECK(lines.metrics()[0].telegrams == 5);
  CHECK_FALSE(lines.stopping());
  CHECK(std::chrono::steady_clock::now() - t0 < 2s);
  hung.release();
  lines.wait_idle();
  CHECK(other == 11);
}

TEST_CASE("serve line workers: a stop drops the queued tasks, each told it never runs",
          "[serve][workers]") {
  std::mutex mu;
  std::vector<std::string> said;
  Gate hung;
  {
    LineWorkers lines(1);
    lines.start([&](std::size_t, Task& t) { t.fn(true); },
                [&](std::deque<Task>& left) {
                  for (auto& t : left) t.fn(false);
                });
    REQUIRE(lines.push(0, fn_task([&](bool) { hung.wait(); })));
    REQUIRE(hung.wait_reached(5s));
    for (const char* name : {"a", "b"}) {
      REQUIRE(lines.push(0, fn_task([&, name](bool run) {
                           std::lock_guard<std::mutex> lock(mu);
                           said.push_back(std::string(name) + (run ? " ran" : " dropped"));
                         })));
    }
    lines.stop();
    CHECK(lines.stopping());
    CHECK_FALSE(lines.push(0, fn_task([](bool) {})));
    lines.wait_idle();  // returns at once when stopping
    hung.release();
  }  // joined
  CHECK(said == std::vector<std::string>{"a dropped", "b dropped"});
}

TEST_CASE("serve line workers: a line's numbers add up over its runs", "[serve][workers]") {
  LineWorkers lines(2);
  lines.count(1, LineMetrics{10, 2, 1, 1, 1, 1.5, 1.5});
  lines.count(1, LineMetrics{4, 0, 0, 0, 1, 0.25, 0.25});
  const auto m = lines.metrics();
  REQUIRE(m.size() == 2);
  CHECK(m[0].runs == 0);
  CHECK(m[1].telegrams == 14);
  CHECK(m[1].retries == 2);
  CHECK(m[1].timeouts == 1);
  CHECK(m[1].errors == 1);
  CHECK(m[1].runs == 2);
  CHECK(m[1].run_seconds == Approx(1.75));
  CHECK(m[1].last_run_seconds == Approx(0.25));
}

}  // namespace serve_test_line_workers
