#pragma once
// Files and directories for the tests: one copy instead of one per test file.
#include <unistd.h>

#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <sstream>
#include <string>

namespace lmcfg::test {

// An empty directory of this test process: TMPDIR/lmcfg-NAME-PID (emptied first).
inline std::filesystem::path temp_dir(const std::string& name) {
  auto d =
      std::filesystem::temp_directory_path() / ("lmcfg-" + name + "-" + std::to_string(::getpid()));
  std::filesystem::remove_all(d);
  std::filesystem::create_directories(d);
  return d;
}

// The whole file, bytes as they are; "" when it cannot be read.
inline std::string slurp(const std::filesystem::path& p) {
  std::ifstream in(p, std::ios::binary);
  std::ostringstream s;
  s << in.rdbuf();
  return s.str();
}

// A directory of one test's own, removed afterwards:
// TMPDIR/lmcfg-PREFIX-PID-N (N counts within the process).
struct ScratchDir {
  std::filesystem::path path;
  explicit ScratchDir(const std::string& prefix) {
    static int n = 0;
    path = std::filesystem::temp_directory_path() /
           ("lmcfg-" + prefix + "-" + std::to_string(::getpid()) + "-" + std::to_string(++n));
    std::filesystem::remove_all(path);
    std::filesystem::create_directories(path);
  }
  ~ScratchDir() {
    std::error_code ec;
    std::filesystem::remove_all(path, ec);
  }
  ScratchDir(const ScratchDir&) = delete;
  ScratchDir& operator=(const ScratchDir&) = delete;
};

// setenv(3)/unsetenv(3) for the tests; MinGW's C library has neither
// (_putenv_s with an empty value removes the variable there).
inline void set_env(const char* name, const char* value) {
#ifdef _WIN32
  ::_putenv_s(name, value);
#else
  ::setenv(name, value, 1);
#endif
}
inline void unset_env(const char* name) {
#ifdef _WIN32
  ::_putenv_s(name, "");
#else
  ::unsetenv(name);
#endif
}

// Replaces the file's content with `text`.
inline void spit(const std::filesystem::path& p, const std::string& text) {
  std::ofstream out(p, std::ios::binary | std::ios::trunc);
  out << text;
}

}  // namespace lmcfg::test
