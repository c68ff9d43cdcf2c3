#pragma once
// "simvanish:STATE.json": the simulated drive (sim::state_file_link_factory,
// as "sim:"), whose link closes after `fail_after` writes of one session
// (-1: never), as a drive unplugged or switched off mid-write. Each
// session's write count is kept, so a test can place the failure after the
// reads a plan makes. It vanishes once: the link that closes sets
// `fail_after` back to -1, so the next session finds the drive again, as
// when it is plugged in again.
#include <atomic>
#include <memory>
#include <mutex>
#include <vector>

#include "link/port.hpp"
#include "sim/state_file.hpp"

namespace lmcfg::test {

struct Vanish {
  std::atomic<long> fail_after{-1};
  std::mutex mu;
  std::vector<long> counts;
};

inline Vanish& vanish() {
  static Vanish v;
  return v;
}

// The writes the newest closed session made (0 before any).
inline long last_session_writes() {
  std::lock_guard<std::mutex> lock(vanish().mu);
  return vanish().counts.empty() ? 0 : vanish().counts.back();
}

class VanishingLink final : public transport::Transport {
 public:
  explicit VanishingLink(std::unique_ptr<transport::Transport> inner)
      : inner_(std::move(inner)), limit_(vanish().fail_after.load()) {}
  ~VanishingLink() override {
    std::lock_guard<std::mutex> lock(vanish().mu);
    vanish().counts.push_back(writes_);
  }
  Result<void> write(ByteView bytes) override {
    if (gone_ || (limit_ >= 0 && writes_ >= limit_)) {
      if (!gone_) vanish().fail_after = -1;  // once
      gone_ = true;
      return Error(Errc::link_closed, "the simulated drive vanished");
    }
    ++writes_;
    return inner_->write(bytes);
  }
  Result<Bytes> read_some(transport::Millis timeout) override {
    if (gone_) return Error(Errc::link_closed, "the simulated drive vanished");
    return inner_->read_some(timeout);
  }
  void discard_input() override { inner_->discard_input(); }
  std::string describe() const override { return "vanishing " + inner_->describe(); }
  double byte_time_us() const override { return inner_->byte_time_us(); }
  Result<void> reconfigure(const transport::SerialSettings& st) override {
    return inner_->reconfigure(st);
  }
  std::int64_t now_ns() const override { return inner_->now_ns(); }

 private:
  std::unique_ptr<transport::Transport> inner_;
  long limit_;
  long writes_ = 0;
  bool gone_ = false;
};

// Registered once for the test binary, whichever test files include this.
inline const bool kVanishRegistered = [] {
  link::register_scheme("simvanish",
                        [](const transport::LinkRequest& r) -> Result<transport::OpenedLink> {
                          static const auto sim = sim::state_file_link_factory();
                          auto opened = sim(r);
                          if (!opened.ok()) return opened;
                          opened->link = std::make_unique<VanishingLink>(std::move(opened->link));
                          return opened;
                        });
  return true;
}();

}  // namespace lmcfg::test
