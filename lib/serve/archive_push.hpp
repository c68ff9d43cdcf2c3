#pragma once
// Private to the serve layer: [archive] push (docs/serve.md "Pushing the
// archive"), a thread of its own with its own handle on the repository and
// its own lock. Not installed.
#include <chrono>
#include <condition_variable>
#include <cstdint>
#include <functional>
#include <mutex>
#include <optional>
#include <string>
#include <thread>

#include "fleet/archive.hpp"
#include "serve/service.hpp"

namespace lmcfg::serve::detail {

class Pusher {
 public:
  struct Options {
    std::string archive, remote;  // the repository's directory; where it is pushed
    std::chrono::milliseconds retry_first{1000}, retry_max{std::chrono::minutes(5)};
    std::function<TimePoint()> clock;
    std::function<void(const std::string&)> log;
    // An event about the archive: push_failed (with its reason), push_recovered.
    std::function<void(const std::string& event, Json details)> emit;
  };
  // What /metrics shows of it.
  struct Stats {
    bool pending = false;  // a commit is not pushed yet
    std::uint64_t failures = 0;
    std::optional<TimePoint> last_success;
  };

  explicit Pusher(Options o);
  ~Pusher();  // stop() and the thread joined
  Pusher(const Pusher&) = delete;
  Pusher& operator=(const Pusher&) = delete;

  // The thread begins; `unpushed`: commits of an earlier run may not be
  // pushed yet (they go with the first push).
  void start(bool unpushed);
  // A commit was made: the thread pushes the branch as it then is, so
  // commits made during a push go with the next one.
  void want();
  void stop();
  Stats stats() const;

 private:
  void loop();
  // One push, outside the lock: its result (a throw is a failed push).
  Result<void> push_once(Result<fleet::Archive>& repo);

  const Options opt_;
  mutable std::mutex mu_;
  std::condition_variable cv_;
  std::uint64_t wanted_ = 0, done_ = 0, failures_ = 0;
  std::optional<TimePoint> last_success_;
  bool failing_ = false;  // in a failure episode (push_failed sent, no success since)
  bool stopping_ = false;
  std::thread thread_;
};

}  // namespace lmcfg::serve::detail
