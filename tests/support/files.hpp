#pragma once
// Files and directories for the tests: one copy instead of one per test file.
#include <unistd.h>

#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <sstream>
#include <string>

namespace lmcfg::test {

// std::filesystem::remove_all, which on Windows first makes the tree's
// read-only files writable: there a read-only file (git's objects) cannot be
// removed, and a tree left behind would be met again by a later run whose
// process has the same ID (Wine reuses small IDs).
inline void remove_tree(const std::filesystem::path& p, std::error_code& ec) {
#ifdef _WIN32
  namespace fs = std::filesystem;
  for (auto it = fs::recursive_directory_iterator(p, ec); !ec && it != fs::end(it);
       it.increment(ec))
    fs::permissions(it->path(), fs::perms::owner_write, fs::perm_options::add, ec);
  ec.clear();
#endif
  std::filesystem::remove_all(p, ec);
}
inline void remove_tree(const std::filesystem::path& p) {
  std::error_code ec;
  remove_tree(p, ec);
  if (ec) throw std::filesystem::filesystem_error("cannot remove the tree", p, ec);
}

// An empty directory of this test process: TMPDIR/lmcfg-NAME-PID (emptied first).
inline std::filesystem::path temp_dir(const std::string& name) {
  auto d =
      std::filesystem::temp_directory_path() / ("lmcfg-" + name + "-" + std::to_string(::getpid()));
  remove_tree(d);
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
    remove_tree(path);
    std::filesystem::create_directories(path);
  }
  ~ScratchDir() {
    std::error_code ec;
    remove_tree(path, ec);
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

// An executable shell script DIR/NAME: "#!/bin/sh" and `body` (POSIX).
inline std::filesystem::path shell_script(const std::filesystem::path& dir, const std::string& name,
                                          const std::string& body) {
  const auto p = dir / name;
  spit(p, "#!/bin/sh\n" + body);
  std::filesystem::permissions(p, std::filesystem::perms::owner_all);
  return p;
}

}  // namespace lmcfg::test
