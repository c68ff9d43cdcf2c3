// `lmcfg sim`'s stop request and stdin end on Windows (sim_platform.hpp):
// SetConsoleCtrlHandler; stdin's end is seen on a pipe (PeekNamedPipe) or a
// file, not on a console (a console has no end of file to poll).
#ifndef WIN32_LEAN_AND_MEAN
#define WIN32_LEAN_AND_MEAN
#endif
#include <windows.h>

#include <atomic>

#include "sim_platform.hpp"

namespace lmcfg::cli {
namespace {

std::atomic<bool> g_sim_stop{false};

BOOL WINAPI on_sim_ctrl(DWORD) {
  g_sim_stop = true;
  return TRUE;  // handled: the serve loop ends and the state is saved
}

}  // namespace

void install_sim_stop_handlers() { ::SetConsoleCtrlHandler(on_sim_ctrl, TRUE); }

bool sim_stop_requested() { return g_sim_stop; }

bool stdin_at_eof() {
  const HANDLE in = ::GetStdHandle(STD_INPUT_HANDLE);
  if (in == nullptr || in == INVALID_HANDLE_VALUE) return true;
  switch (::GetFileType(in)) {
    case FILE_TYPE_PIPE: {
      DWORD avail = 0;
      if (!::PeekNamedPipe(in, nullptr, 0, nullptr, &avail, nullptr))
        return ::GetLastError() == ERROR_BROKEN_PIPE;
      char buf[256];
      DWORD got = 0;
      if (avail > 0) ::ReadFile(in, buf, avail < sizeof buf ? avail : sizeof buf, &got, nullptr);
      return false;
    }
    case FILE_TYPE_DISK: {
      char buf[256];
      DWORD got = 0;
      return ::ReadFile(in, buf, sizeof buf, &got, nullptr) && got == 0;
    }
    default:
      return false;
  }
}

bool sim_has_pty() { return false; }

}  // namespace lmcfg::cli
