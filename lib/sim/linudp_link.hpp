#pragma once
// The in-process link to a simulated LinUDP drive: transport::Transport over
// sim::LinudpDrive on a VirtualClock (sim/link.hpp), so the tests of long
// steps (39-75 s saves, silences of 30-90 s) take no real seconds. One
// write() is one datagram; read_some() hands out one reply datagram once its
// time has come, or advances the clock by the timeout.
#include <deque>
#include <memory>

#include "sim/link.hpp"
#include "sim/linudp_drive.hpp"

namespace lmcfg::sim {

class LinudpLink : public transport::Transport {
 public:
  explicit LinudpLink(std::shared_ptr<LinudpDrive> drive) : drive_(std::move(drive)) {}

  Result<void> write(ByteView bytes) override;
  Result<Bytes> read_some(transport::Millis timeout) override;
  void discard_input() override;
  std::string describe() const override { return "linudp-sim"; }
  std::int64_t now_ns() const override { return clock_.now_ns(); }

  VirtualClock& clock() { return clock_; }
  LinudpDrive& drive() { return *drive_; }
  std::uint64_t datagrams_sent() const { return sent_; }

 private:
  struct Timed {
    Bytes bytes;
    std::int64_t ready_ns = 0;
  };
  std::shared_ptr<LinudpDrive> drive_;
  VirtualClock clock_;
  std::deque<Timed> pending_;
  std::uint64_t sent_ = 0;
};

}  // namespace lmcfg::sim
