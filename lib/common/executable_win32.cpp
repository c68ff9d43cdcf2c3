#ifndef WIN32_LEAN_AND_MEAN
#define WIN32_LEAN_AND_MEAN
#endif
#include <windows.h>

#include <string>

#include "common/executable.hpp"

namespace lmcfg {

Result<std::filesystem::path> running_executable() {
  std::wstring buf(MAX_PATH, L'\0');
  for (;;) {
    const DWORD n = ::GetModuleFileNameW(nullptr, buf.data(), static_cast<DWORD>(buf.size()));
    if (n == 0)
      return Error(Errc::file_error,
                   "cannot locate the running executable (GetModuleFileNameW "
                   "failed with error " +
                       std::to_string(::GetLastError()) + ")");
    if (n < buf.size()) {
      buf.resize(n);
      return std::filesystem::path(buf);
    }
    buf.resize(buf.size() * 2);  // a long path: try again with room for it
  }
}

}  // namespace lmcfg
