#include "sim/linudp_link.hpp"

#include <algorithm>

namespace lmcfg::sim {

namespace {
// A datagram's time on a local network: small against the drive's
// turnaround; a fixed figure keeps the virtual clock deterministic.
constexpr std::int64_t kNetworkNs = 100'000;
}  // namespace

Result<void> LinudpLink::write(ByteView bytes) {
  ++sent_;
  clock_.advance_ns(kNetworkNs);
  const std::int64_t now = clock_.now_ns();
  for (auto& a : drive_->receive(bytes, now))
    pending_.push_back({std::move(a.bytes), now + a.delay_ns + kNetworkNs});
  std::stable_sort(pending_.begin(), pending_.end(),
                   [](const Timed& a, const Timed& b) { return a.ready_ns < b.ready_ns; });
  return {};
}

Result<Bytes> LinudpLink::read_some(transport::Millis timeout) {
  const std::int64_t until =
      clock_.now_ns() + static_cast<std::int64_t>(timeout.count()) * 1'000'000;
  if (!pending_.empty() && pending_.front().ready_ns <= until) {
    clock_.advance_to_ns(pending_.front().ready_ns);
    Bytes b = std::move(pending_.front().bytes);
    pending_.pop_front();
    return b;
  }
  clock_.advance_to_ns(until);
  return Bytes{};
}

void LinudpLink::discard_input() {
  // Datagrams already arrived (ready by now) are dropped; later ones stay.
  const std::int64_t now = clock_.now_ns();
  pending_.erase(std::remove_if(pending_.begin(), pending_.end(),
                                [&](const Timed& t) { return t.ready_ns <= now; }),
                 pending_.end());
}

}  // namespace lmcfg::sim
