#pragma once
// What the operations ask of the operating system, one function per concern:
// platform.cpp (POSIX) and platform_win32.cpp (Windows) implement it.
#include <filesystem>
#include <string>

#include "common/result.hpp"

namespace lmcfg::ops {

// Where lmcfg keeps its state (recovery and undo records, the journal):
// $XDG_STATE_HOME/lmcfg (absolute), else ~/.local/state/lmcfg; on Windows
// %LOCALAPPDATA%\lmcfg. Errc::file_error when none of them is set.
Result<std::filesystem::path> state_dir();

// current_user() (ops/audit.hpp) is implemented beside state_dir() too.

}  // namespace lmcfg::ops
