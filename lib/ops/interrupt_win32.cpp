// Windows: Ctrl-C and Ctrl-Break arrive as console control events on a
// thread of their own (SetConsoleCtrlHandler). The handler only sets the flag,
// as the POSIX signal handler does (interrupt.hpp): the telegram in flight
// completes, the operation stops before the next one, the tool exits 130.
#ifndef WIN32_LEAN_AND_MEAN
#define WIN32_LEAN_AND_MEAN
#endif
#include <windows.h>

#include <chrono>
#include <cstdint>
#include <cstdlib>

#include "ops/interrupt.hpp"

namespace lmcfg::ops {

namespace {
std::atomic<bool> g_interrupted{false};
std::atomic<std::int64_t> g_first_ms{0};

std::int64_t now_ms() {
  return std::chrono::duration_cast<std::chrono::milliseconds>(
             std::chrono::steady_clock::now().time_since_epoch())
      .count();
}

// A second Ctrl-C more than a second after the first ends the process at
// once (interrupt.hpp). Returning TRUE keeps Windows from ending it.
BOOL WINAPI on_console_event(DWORD type) {
  if (type != CTRL_C_EVENT && type != CTRL_BREAK_EVENT && type != CTRL_CLOSE_EVENT) return FALSE;
  const std::int64_t now = now_ms();
  if (!g_interrupted.exchange(true)) {
    g_first_ms = now;
    return TRUE;
  }
  if (now - g_first_ms.load() > 1000) std::_Exit(130);
  return TRUE;
}
}  // namespace

std::atomic<bool>& interrupt_flag() { return g_interrupted; }

void install_interrupt_handlers() { ::SetConsoleCtrlHandler(on_console_event, TRUE); }

}  // namespace lmcfg::ops
