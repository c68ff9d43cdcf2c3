#pragma once
// What `lmcfg ui` asks of the desktop (ui_platform.cpp: Linux's xdg-open,
// ui_platform_win32.cpp: ShellExecute), beside the library's page.
#include <string>

namespace lmcfg::cli {

// Opens `url` in the user's default browser without waiting for it; false
// when no opener could be started (the tool then says to open it by hand).
bool open_browser(const std::string& url);
// Where backups go unless --folder says: ~/lmcfg (Windows:
// %USERPROFILE%\Documents\lmcfg); "lmcfg" in the current folder when no home is known.
std::string default_ui_folder();

}  // namespace lmcfg::cli
