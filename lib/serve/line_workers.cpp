// The service's line workers (docs/serve.md): a line's drives share one
// bus, so one thread per line runs its tasks in turn; the queues' lock is
// released while a task runs, so a drive that never answers holds its line's
// worker and nothing else.
#include "serve/line_workers.hpp"

namespace lmcfg::serve::detail {

LineWorkers::LineWorkers(std::size_t lines)
    : queues_(lines), busy_(lines, false), metrics_(lines) {}

LineWorkers::~LineWorkers() {
  stop();
  join();
}

void LineWorkers::start(Run run, Drop drop) {
  run_ = std::move(run);
  drop_ = std::move(drop);
  for (std::size_t l = 0; l < queues_.size(); ++l) threads_.emplace_back([this, l] { worker(l); });
}

bool LineWorkers::push(std::size_t line, Task task) {
  std::lock_guard<std::mutex> lock(mu_);
  if (stopping_) return false;
  queues_[line].push_back(std::move(task));
  cv_.notify_all();
  return true;
}

std::size_t LineWorkers::queued(std::size_t line,
                                const std::function<bool(const Task&)>& pred) const {
  std::lock_guard<std::mutex> lock(mu_);
  std::size_t n = 0;
  for (const auto& t : queues_[line]) n += pred(t) ? 1 : 0;
  return n;
}

void LineWorkers::wait_idle() {
  std::unique_lock<std::mutex> lock(mu_);
  cv_.wait(lock, [&] {
    if (stopping_) return true;
    for (std::size_t l = 0; l < queues_.size(); ++l)
      if (!queues_[l].empty() || busy_[l]) return false;
    return true;
  });
}

void LineWorkers::stop() {
  std::lock_guard<std::mutex> lock(mu_);
  stopping_ = true;
  cv_.notify_all();
}

void LineWorkers::join() {
  for (auto& t : threads_)
    if (t.joinable()) t.join();
}

bool LineWorkers::stopping() const {
  std::lock_guard<std::mutex> lock(mu_);
  return stopping_;
}

void LineWorkers::count(std::size_t line, const LineMetrics& run) {
  std::lock_guard<std::mutex> lock(mu_);
  auto& m = metrics_[line];
  m.telegrams += run.telegrams;
  m.retries += run.retries;
  m.timeouts += run.timeouts;
  m.errors += run.errors;
  m.runs += run.runs;
  m.run_seconds += run.run_seconds;
  m.last_run_seconds = run.last_run_seconds;
}

std::vector<LineMetrics> LineWorkers::metrics() const {
  std::lock_guard<std::mutex> lock(mu_);
  return metrics_;
}

void LineWorkers::worker(std::size_t line) {
  std::unique_lock<std::mutex> lock(mu_);
  for (;;) {
    cv_.wait(lock, [&] { return stopping_ || !queues_[line].empty(); });
    if (stopping_) {
      std::deque<Task> left = std::move(queues_[line]);
      queues_[line].clear();
      lock.unlock();
      if (drop_) drop_(left);
      return;
    }
    Task task = std::move(queues_[line].front());
    queues_[line].pop_front();
    busy_[line] = true;
    lock.unlock();
    run_(line, task);
    lock.lock();
    busy_[line] = false;
    cv_.notify_all();
  }
}

}  // namespace lmcfg::serve::detail
