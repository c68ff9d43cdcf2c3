// [archive] push (docs/serve.md "Pushing the archive"): the push thread. Its
// own handle on the repository: a slow or unreachable remote holds neither
// the archive's lock nor a line's worker, so backups and commits go on and
// only the push waits; a failed push is tried again later, each wait twice
// the last up to retry_max.
#include "serve/archive_push.hpp"

#include <algorithm>

#include "fleet/archive.hpp"

namespace lmcfg::serve::detail {

Pusher::Pusher(Options o) : opt_(std::move(o)) {}

Pusher::~Pusher() {
  stop();
  if (thread_.joinable()) thread_.join();
}

void Pusher::start(bool unpushed) {
  {
    std::lock_guard<std::mutex> lock(mu_);
    if (unpushed) wanted_ = std::max<std::uint64_t>(wanted_, 1);
  }
  thread_ = std::thread([this] { loop(); });
}

void Pusher::want() {
  std::lock_guard<std::mutex> lock(mu_);
  ++wanted_;
  cv_.notify_all();
}

void Pusher::stop() {
  std::lock_guard<std::mutex> lock(mu_);
  stopping_ = true;
  cv_.notify_all();
}

Pusher::Stats Pusher::stats() const {
  std::lock_guard<std::mutex> lock(mu_);
  return Stats{wanted_ > done_, failures_, last_success_};
}

Result<void> Pusher::push_once(Result<fleet::Archive>& repo) {
  if (!repo.ok()) return repo.error();
  // A throw on this thread would end the process: it is a failed push.
  try {
    return repo->push(opt_.remote);
  } catch (const std::exception& e) {
    return Error(Errc::io_error, std::string("push: internal error: ") + e.what());
  }
}

void Pusher::loop() {
  auto repo = fleet::Archive::open(opt_.archive, false);
  std::chrono::milliseconds wait = opt_.retry_first;
  std::unique_lock<std::mutex> lock(mu_);
  for (;;) {
    cv_.wait(lock, [&] { return stopping_ || wanted_ > done_; });
    if (stopping_) return;
    const std::uint64_t asked = wanted_;
    lock.unlock();
    Result<void> pushed = push_once(repo);
    lock.lock();
    if (pushed.ok()) {
      done_ = std::max(done_, asked);
      last_success_ = opt_.clock();
      wait = opt_.retry_first;
      const bool recovered = std::exchange(failing_, false);
      lock.unlock();
      opt_.log("pushed the archive to " + opt_.remote);
      if (recovered) opt_.emit("push_recovered", Json::object());
      lock.lock();
      continue;
    }
    ++failures_;
    const bool first = !std::exchange(failing_, true);
    lock.unlock();
    opt_.log("push to " + opt_.remote + " failed, next try in " + std::to_string(wait.count()) +
             " ms: " + pushed.error().message);
    if (first) opt_.emit("push_failed", {{"reason", pushed.error().message}});
    lock.lock();
    cv_.wait_for(lock, wait, [&] { return stopping_; });
    wait = std::min(wait * 2, opt_.retry_max);
  }
}

}  // namespace lmcfg::serve::detail
