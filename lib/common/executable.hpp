#pragma once
// The path of the running program (the UPID database is looked for next to
// it): /proc/self/exe on Linux (executable.cpp), GetModuleFileNameW on Windows
// (executable_win32.cpp). Errc::file_error saying why when it cannot be known.
#include <filesystem>

#include "common/result.hpp"

namespace lmcfg {

Result<std::filesystem::path> running_executable();

}  // namespace lmcfg
