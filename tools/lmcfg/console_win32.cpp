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

}  // namespace lmcfg::cli
