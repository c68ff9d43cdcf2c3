#include "sim/server.hpp"

#include <algorithm>
#include <chrono>
#include <cstring>
#include <vector>

#include "sim/link.hpp"

namespace lmcfg::sim {

Result<void> serve(Drive& drive, transport::Transport& link, const ServeOptions& opt,
                   ServeStats* stats) {
  return serve_bus({&drive}, link, opt, stats);
}

Result<void> serve_bus(const std::vector<Drive*>& drives, transport::Transport& link,
                       const ServeOptions& opt, ServeStats* stats) {
  // One continuous clock for every connection a drive is served on: in real
  // time the steady clock (a drive reset just before a reconnect is still
  // resetting), else the steady clock plus the delays nobody waited for, so a
  // drive started (ca. 3 s, §13.4) in the last connection is idle in this one.
  using clock = std::chrono::steady_clock;
  auto steady_ns = [] {
    return std::chrono::duration_cast<std::chrono::nanoseconds>(clock::now().time_since_epoch())
        .count();
  };
  std::int64_t skipped_ns = 0;
  if (!opt.real_time) {
    for (const Drive* d : drives) skipped_ns = std::max(skipped_ns, d->idle_at_ns() - steady_ns());
  }
  auto now_ns = [&] { return steady_ns() + skipped_ns; };
  struct Due {
    std::int64_t at_ns;
    Bytes bytes;
    const Drive* from;
  };
  std::vector<Due> pending;  // sorted by at_ns
  ServeStats local;
  ServeStats& st = stats ? *stats : local;
  // Every drive hears every byte at its own baud rate; only the addressed one
  // answers (an RS485 line, LinRS §2).
  auto wrong_baud = [&](const Drive& d) {
    if (!opt.master_baud) return false;
    const auto b = opt.master_baud();
    return b && *b != d.state().link.baud;
  };

  while (!(opt.should_stop && opt.should_stop())) {
    auto wait = opt.poll;
    if (!pending.empty()) {
      const auto left_ns = pending.front().at_ns - now_ns();
      wait = std::min(
          wait, transport::Millis(std::max<std::int64_t>(0, (left_ns + 999'999) / 1'000'000)));
    }
    auto r = link.read_some(wait);
    if (!r.ok()) return std::move(r).error();
    const auto t = now_ns();
    if (!r->empty()) {
      st.bytes_in += r->size();
      if (opt.trace) opt.trace(false, *r);
      for (Drive* drive : drives) {
        if (wrong_baud(*drive)) {
          st.bytes_at_wrong_baud += r->size();
          continue;
        }
        for (auto& a : drive->receive(*r, t)) {
          std::int64_t at = t;
          if (opt.real_time) {
            at += a.delay_ns + wire_time_ns(a.bytes.size(), drive->state().link);
          } else {
            skipped_ns += a.delay_ns;
          }
          auto pos = std::upper_bound(pending.begin(), pending.end(), at,
                                      [](std::int64_t v, const Due& d) { return v < d.at_ns; });
          pending.insert(pos, Due{at, std::move(a.bytes), drive});
        }
      }
    }
    while (!pending.empty() && pending.front().at_ns <= now_ns()) {
      Bytes out = std::move(pending.front().bytes);
      const Drive* from = pending.front().from;
      pending.erase(pending.begin());
      if (wrong_baud(*from)) {  // e.g. the drive rebooted at another rate before answering
        st.bytes_at_wrong_baud += out.size();
        continue;
      }
      if (opt.trace) opt.trace(true, out);
      if (auto w = link.write(out); !w.ok()) return std::move(w).error();
      st.bytes_out += out.size();
      ++st.answers;
    }
  }
  return {};
}

}  // namespace lmcfg::sim
