#pragma once
// Private to the serve layer: one worker thread per line with its queue of
// tasks, and the line's numbers for /metrics, under their own lock. The lock
// is never held while a task runs (a task reads drives). Not installed.
#include <condition_variable>
#include <cstdint>
#include <deque>
#include <functional>
#include <memory>
#include <mutex>
#include <thread>
#include <vector>

#include "serve/job_table.hpp"

namespace lmcfg::serve::detail {

struct Task {
  std::shared_ptr<Job> job;
  std::vector<std::string> only;  // drive names; empty = the whole line
  // Work other than a backup or drift check (plans, restores, live reads), run
  // on the line's worker: fn(true); fn(false) when the service stops first.
  std::function<void(bool run)> fn;
};

struct LineMetrics {
  std::uint64_t telegrams = 0, retries = 0, timeouts = 0, errors = 0, runs = 0;
  double run_seconds = 0, last_run_seconds = 0;
};

class LineWorkers {
 public:
  // Runs `task` on line `line`'s worker (no lock held).
  using Run = std::function<void(std::size_t line, Task& task)>;
  // The tasks a stop left queued on a line (no lock held): they never run.
  using Drop = std::function<void(std::deque<Task>& left)>;

  explicit LineWorkers(std::size_t lines);
  ~LineWorkers();  // stop() and the threads joined
  LineWorkers(const LineWorkers&) = delete;
  LineWorkers& operator=(const LineWorkers&) = delete;

  // One thread per line begins taking tasks.
  void start(Run run, Drop drop);
  // Queues `task` on `line` (a job's totals are the caller's); false when
  // the service is stopping (nothing queued).
  bool push(std::size_t line, Task task);
  // The tasks queued (not running) on `line` that `pred` accepts. `pred`
  // runs under the lock: it may read a task's job's fixed fields only.
  std::size_t queued(std::size_t line, const std::function<bool(const Task&)>& pred) const;
  // Until every queue is empty and no task runs (or the service stops).
  void wait_idle();
  void stop();
  void join();
  bool stopping() const;

  // A run on `line` ended: its telegrams and time into the line's numbers.
  void count(std::size_t line, const LineMetrics& run);
  std::vector<LineMetrics> metrics() const;

 private:
  void worker(std::size_t line);

  mutable std::mutex mu_;
  std::condition_variable cv_;
  std::vector<std::deque<Task>> queues_;  // one per line
  std::vector<bool> busy_;
  std::vector<LineMetrics> metrics_;
  bool stopping_ = false;
  Run run_;
  Drop drop_;
  std::vector<std::thread> threads_;
};

}  // namespace lmcfg::serve::detail
