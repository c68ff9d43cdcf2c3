// lmcfg_bench_rfc2217: the cost of one LinRS exchange through ser2net's RFC 2217
// accepter against the same exchange on the pseudo-terminal directly
// (docs/measurements.md, docs/transport.md "RFC 2217"). A simulated drive (lib/sim, real time: it
// answers after its modelled turnaround plus the answer's wire time at
// 57600 Bd) is served on a pty; N read-RAM exchanges of LinRS §9.1
// (01 11 05 02 00 03 A2 13 04, a 20-byte answer) run first with open_serial on
// the pty's slave, then with open_rfc2217 through ser2net serving that slave.
// Round trip = write() of the request to the last byte of a complete answer.
//
//   build/bench/lmcfg_bench_rfc2217 [--count N] [--no-chardelay]
//
// --no-chardelay: ser2net's "chardelay: false" (it otherwise waits for a gap of
// a few character times on the serial side before sending what it read).
//
// Without ser2net (Debian package ser2net; $LMCFG_SER2NET names another
// binary) it prints why and exits 0. Exit status 1 when an exchange fails.
#include <algorithm>
#include <atomic>
#include <chrono>
#include <cstdio>
#include <cstring>
#include <string>
#include <thread>
#include <vector>

#include "codec/frame.hpp"
#include "ser2net_rig.hpp"
#include "sim/server.hpp"
#include "sim/state_file.hpp"
#include "transport/pty.hpp"
#include "transport/rfc2217.hpp"

using namespace lmcfg;
using namespace std::chrono_literals;

namespace {

struct Figures {
  double median_us = 0, p99_us = 0, min_us = 0, max_us = 0, mean_us = 0;
};

Figures summarize(std::vector<double> us) {
  std::sort(us.begin(), us.end());
  Figures f;
  f.min_us = us.front();
  f.max_us = us.back();
  f.median_us = us[us.size() / 2];
  f.p99_us = us[std::min(us.size() - 1, (us.size() * 99) / 100)];
  double sum = 0;
  for (double v : us) sum += v;
  f.mean_us = sum / static_cast<double>(us.size());
  return f;
}

// N exchanges; empty on failure (the reason printed).
std::vector<double> run(transport::Transport& link, int count) {
  const Bytes req = from_hex("01 11 05 02 00 03 A2 13 04").value();
  std::vector<double> out;
  out.reserve(static_cast<std::size_t>(count));
  for (int i = 0; i < count; ++i) {
    codec::StreamDecoder dec;
    const auto t0 = std::chrono::steady_clock::now();
    if (auto w = link.write(req); !w.ok()) {
      std::fprintf(stderr, "write failed: %s\n", w.error().message.c_str());
      return {};
    }
    bool done = false;
    while (!done) {
      auto r = link.read_some(transport::Millis(1000));
      if (!r.ok() || r->empty()) {
        std::fprintf(stderr, "exchange %d: %s\n", i,
                     r.ok() ? "no answer within 1 s" : r.error().message.c_str());
        return {};
      }
      dec.feed(*r);
      if (auto f = dec.next(); f && f->ok()) done = true;
    }
    const auto t1 = std::chrono::steady_clock::now();
    out.push_back(std::chrono::duration<double, std::micro>(t1 - t0).count());
  }
  return out;
}

void print(const char* name, const Figures& f) {
  std::printf("%-34s median %8.1f us  p99 %8.1f us  mean %8.1f us  min %8.1f us  max %8.1f us\n",
              name, f.median_us, f.p99_us, f.mean_us, f.min_us, f.max_us);
}

}  // namespace

int main(int argc, char** argv) {
  int count = 1000;
  std::string options;
  for (int i = 1; i < argc; ++i) {
    if (!std::strcmp(argv[i], "--count") && i + 1 < argc) {
      count = std::atoi(argv[++i]);
    } else if (!std::strcmp(argv[i], "--no-chardelay")) {
      options = "    chardelay: false\n";
    } else {
      std::fprintf(stderr, "usage: %s [--count N] [--no-chardelay]\n", argv[0]);
      return 2;
    }
  }
  if (count < 1) {
    std::fprintf(stderr, "lmcfg_bench_rfc2217: --count must be at least 1\n");
    return 2;
  }
  if (const std::string why = test::ser2net_missing(); !why.empty()) {
    std::printf("lmcfg_bench_rfc2217: SKIP: %s\n", why.c_str());
    return 0;
  }
  auto state = sim::load_state(LMCFG_SOURCE_DIR "/tests/fixtures/sim/manual-drive.json");
  if (!state.ok()) {
    std::fprintf(stderr, "lmcfg_bench_rfc2217: %s\n", state.error().message.c_str());
    return 1;
  }
  state->macid = 0x11;
  state->link.baud = 57600;
  sim::Drive drive(std::move(state).value());

  auto pty = transport::open_pty();
  if (!pty.ok()) {
    std::fprintf(stderr, "lmcfg_bench_rfc2217: %s\n", pty.error().message.c_str());
    return 1;
  }
  const std::string slave = pty->slave_path;
  transport::UniqueFd slave_fd = std::move(pty->slave);
  transport::FdTransport master(std::move(pty->master), "pty " + slave);
  std::atomic<bool> stop{false};
  std::thread server([&] {
    sim::ServeOptions o;
    o.real_time = true;
    o.poll = transport::Millis(10);
    o.should_stop = [&] { return stop.load(); };
    o.master_baud = [&] { return transport::line_baud(master.fd()); };
    (void)sim::serve(drive, master, o);
  });

  std::printf(
      "lmcfg_bench_rfc2217: %d read-RAM exchanges (seed 003 §9.1) with a simulated drive in real "
      "time at 57600 8N1, %u hardware threads, ser2net chardelay %s\n",
      count, std::thread::hardware_concurrency(), options.empty() ? "on (default)" : "off");
  int rc = 0;
  std::vector<double> direct, via;
  {
    auto link = transport::open_serial({slave, 57600, transport::Parity::none, 1});
    if (!link.ok()) {
      std::fprintf(stderr, "lmcfg_bench_rfc2217: %s\n", link.error().message.c_str());
      rc = 1;
    } else {
      direct = run(**link, count);
    }
  }
  if (rc == 0 && !direct.empty()) {
    test::Ser2netRig rig(slave, 9600, options);
    if (!rig.ok()) {
      std::fprintf(stderr, "lmcfg_bench_rfc2217: %s\n", rig.error.c_str());
      rc = 1;
    } else {
      auto link = transport::open_rfc2217("127.0.0.1", rig.port,
                                          {"", 57600, transport::Parity::none, 1}, 3000ms);
      if (!link.ok()) {
        std::fprintf(stderr, "lmcfg_bench_rfc2217: %s\n", link.error().message.c_str());
        rc = 1;
      } else {
        via = run(**link, count);
      }
    }
  }
  stop = true;
  server.join();
  if (direct.empty() || via.empty()) return 1;
  const Figures d = summarize(direct), r = summarize(via);
  print("pty direct (open_serial)", d);
  print("ser2net RFC 2217 (open_rfc2217)", r);
  std::printf("added by ser2net + TCP loopback: median %+.1f us, p99 %+.1f us\n",
              r.median_us - d.median_us, r.p99_us - d.p99_us);
  return rc;
}
