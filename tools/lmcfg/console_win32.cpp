#ifndef WIN32_LEAN_AND_MEAN
#define WIN32_LEAN_AND_MEAN
#endif
#include <windows.h>

#include "console.hpp"

namespace lmcfg::cli {

// UTF-8 output ("°C", "µm" in parameter units, names of files) shows as such
// in cmd.exe and PowerShell; the manifest (windows/lmcfg.manifest) makes the
// process's own code page UTF-8 for arguments and paths.
void init_console() {
  ::SetConsoleOutputCP(CP_UTF8);
  ::SetConsoleCP(CP_UTF8);
}

// Explorer starts a console program in a new console made for it alone:
// GetConsoleProcessList then lists one process. Started from cmd.exe or
// PowerShell the console is shared with the shell (two or more). Output sent
// into a file or a pipe is a script's, never a double-click's.
bool started_by_double_click() {
  DWORD ids[2];
  if (::GetConsoleProcessList(ids, 2) != 1) return false;
  HANDLE out = ::GetStdHandle(STD_OUTPUT_HANDLE);
  return out != nullptr && out != INVALID_HANDLE_VALUE && ::GetFileType(out) == FILE_TYPE_CHAR;
}

}  // namespace lmcfg::cli
