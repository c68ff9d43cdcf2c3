// Windows: state under %LOCALAPPDATA%\lmcfg (per user, not roaming: the
// records name this computer's ports), the user from GetUserNameW.
#ifndef WIN32_LEAN_AND_MEAN
#define WIN32_LEAN_AND_MEAN
#endif
#include <windows.h>

#include <cstdlib>

#include "ops/audit.hpp"
#include "ops/platform.hpp"

namespace lmcfg::ops {

namespace fs = std::filesystem;

Result<fs::path> state_dir() {
  if (const wchar_t* app = ::_wgetenv(L"LOCALAPPDATA"); app && *app) return fs::path(app) / "lmcfg";
  if (const wchar_t* profile = ::_wgetenv(L"USERPROFILE"); profile && *profile)
    return fs::path(profile) / "AppData" / "Local" / "lmcfg";
  return Error(Errc::file_error,
               "no place for the recovery record: neither %LOCALAPPDATA% nor %USERPROFILE% is set");
}

std::string current_user() {
  wchar_t name[257] = {};
  DWORD size = 257;
  if (::GetUserNameW(name, &size) && name[0]) {
    const std::u8string utf8 = fs::path(name).u8string();
    return std::string(utf8.begin(), utf8.end());
  }
  if (const char* user = std::getenv("USERNAME"); user && *user) return user;
  return "unknown";
}

}  // namespace lmcfg::ops
