#include "sim/linudp_server.hpp"

#include <algorithm>
#include <deque>

namespace lmcfg::sim {

Result<void> serve_linudp(LinudpDrive& drive, transport::UdpServer& socket,
                          const LinudpServeOptions& opt) {
  struct Due {
    transport::Clock::time_point at;
    transport::UdpServer::Datagram to;
    Bytes bytes;
  };
  std::deque<Due> due;
  const auto origin = transport::Clock::now();
  for (;;) {
    if (opt.should_stop && opt.should_stop()) return {};
    const auto now = transport::Clock::now();
    while (!due.empty() && due.front().at <= now) {
      if (opt.trace) opt.trace(true, due.front().bytes);
      LMCFG_TRY(socket.send_to(due.front().to, due.front().bytes));
      due.pop_front();
    }
    auto wait = opt.poll;
    if (!due.empty())
      wait = std::min(wait, std::chrono::ceil<transport::Millis>(due.front().at - now));
    LMCFG_ASSIGN_OR_RETURN(auto got, socket.receive(std::max(wait, transport::Millis(0))));
    if (!got) continue;
    if (opt.trace) opt.trace(false, got->bytes);
    const auto at = transport::Clock::now();
    const std::int64_t now_ns =
        std::chrono::duration_cast<std::chrono::nanoseconds>(at - origin).count();
    for (auto& a : drive.receive(got->bytes, now_ns, got->from_port)) {
      const auto delay =
          opt.real_time ? std::chrono::nanoseconds(a.delay_ns) : std::chrono::nanoseconds(0);
      due.push_back(Due{at + delay, *got, std::move(a.bytes)});
    }
    std::stable_sort(due.begin(), due.end(),
                     [](const Due& x, const Due& y) { return x.at < y.at; });
  }
}

}  // namespace lmcfg::sim
