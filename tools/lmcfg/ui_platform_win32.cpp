#include <windows.h>
// shellapi.h needs windows.h first.
#include <shellapi.h>

#include <cstdlib>

#include "ui_platform.hpp"

namespace lmcfg::cli {

bool open_browser(const std::string& url) {
  // The URL is ASCII (a loopback address, a port and a hex token).
  const auto r = reinterpret_cast<INT_PTR>(
      ShellExecuteA(nullptr, "open", url.c_str(), nullptr, nullptr, SW_SHOWNORMAL));
  return r > 32;  // ShellExecute's success (its documented convention)
}

std::string default_ui_folder() {
  const char* profile = std::getenv("USERPROFILE");
  return profile && *profile ? std::string(profile) + "\\Documents\\lmcfg" : "lmcfg";
}

}  // namespace lmcfg::cli
