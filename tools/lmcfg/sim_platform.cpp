// `lmcfg sim`'s stop request and stdin end on POSIX (sim_platform.hpp).
#include "sim_platform.hpp"

#include <poll.h>
#include <signal.h>
#include <unistd.h>

namespace lmcfg::cli {
namespace {

volatile sig_atomic_t g_sim_stop = 0;
void on_sim_signal(int) { g_sim_stop = 1; }

}  // namespace

void install_sim_stop_handlers() {
  struct sigaction sa {};
  sa.sa_handler = on_sim_signal;
  sigemptyset(&sa.sa_mask);
  ::sigaction(SIGINT, &sa, nullptr);
  ::sigaction(SIGTERM, &sa, nullptr);
  ::signal(SIGPIPE, SIG_IGN);
}

bool sim_stop_requested() { return g_sim_stop != 0; }

bool stdin_at_eof() {
  pollfd p{STDIN_FILENO, POLLIN, 0};
  if (::poll(&p, 1, 0) <= 0) return false;
  if (p.revents & (POLLHUP | POLLERR | POLLNVAL)) {
    char c;
    return ::read(STDIN_FILENO, &c, 1) <= 0;
  }
  char buf[256];
  return ::read(STDIN_FILENO, buf, sizeof buf) == 0;
}

bool sim_has_pty() { return true; }

}  // namespace lmcfg::cli
