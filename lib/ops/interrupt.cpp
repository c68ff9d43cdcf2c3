#include "ops/interrupt.hpp"

#include <signal.h>
#include <time.h>
#include <unistd.h>

#include <cstdint>

namespace lmcfg::ops {

namespace {
std::atomic<bool> g_interrupted{false};
static_assert(std::atomic<bool>::is_always_lock_free, "the signal handler needs a lock-free flag");

std::atomic<std::int64_t> g_first_ns{0};
static_assert(std::atomic<std::int64_t>::is_always_lock_free);

std::int64_t monotonic_ns() {  // clock_gettime is async-signal-safe (signal-safety(7))
  timespec ts{};
  ::clock_gettime(CLOCK_MONOTONIC, &ts);
  return static_cast<std::int64_t>(ts.tv_sec) * 1'000'000'000 + ts.tv_nsec;
}

// A second signal ends the process at once, but only a second later: one
// Ctrl-C can arrive twice (GNU timeout and some shells signal the process and
// its group), and that must not skip the message naming the step.
extern "C" void on_interrupt(int) {
  const std::int64_t now = monotonic_ns();
  if (!g_interrupted.exchange(true)) {
    g_first_ns = now;
    return;
  }
  if (now - g_first_ns.load() > 1'000'000'000) ::_exit(130);
}
}  // namespace

std::atomic<bool>& interrupt_flag() { return g_interrupted; }

void install_interrupt_handlers() {
  struct sigaction sa {};
  sa.sa_handler = on_interrupt;
  sigemptyset(&sa.sa_mask);
  sa.sa_flags = SA_RESTART;
  ::sigaction(SIGINT, &sa, nullptr);
  ::sigaction(SIGTERM, &sa, nullptr);
}

}  // namespace lmcfg::ops
