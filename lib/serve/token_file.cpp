#include "serve/token_file.hpp"

#include <fcntl.h>
#include <sys/stat.h>
#include <unistd.h>

#include <cerrno>
#include <cstdio>
#include <cstring>
#include <fstream>

namespace lmcfg::serve {

Result<void> check_owner_only(const std::string& path) {
  struct stat st {};
  if (::stat(path.c_str(), &st) == 0 && (st.st_mode & (S_IWGRP | S_IWOTH)) != 0) {
    char mode[8];
    std::snprintf(mode, sizeof mode, "%04o", static_cast<unsigned>(st.st_mode & 07777));
    return Error(Errc::file_error,
                 path + ": the tokens file is writable by " +
                     ((st.st_mode & S_IWOTH) ? "others" : "its group") + " (mode " + mode +
                     "), so anyone there could add a token: run chmod 600 " + path);
  }
  return {};
}

bool file_exists(const std::string& path) { return ::access(path.c_str(), F_OK) == 0; }

Result<void> append_owner_only(const std::string& path, const std::string& line) {
  const int fd = ::open(path.c_str(), O_WRONLY | O_CREAT | O_APPEND | O_CLOEXEC, 0600);
  if (fd < 0) return Error(Errc::file_error, path + ": " + std::strerror(errno));
  const bool ok = ::write(fd, line.data(), line.size()) == static_cast<ssize_t>(line.size());
  const int saved = errno;
  ::close(fd);
  if (!ok) return Error(Errc::file_error, path + ": " + std::strerror(saved));
  return {};
}

Result<std::vector<std::uint8_t>> random_bytes(std::size_t n) {
  std::vector<std::uint8_t> raw(n);
  std::ifstream rnd("/dev/urandom", std::ios::binary);
  if (!rnd.read(reinterpret_cast<char*>(raw.data()), static_cast<std::streamsize>(raw.size())))
    return Error(Errc::io_error, "/dev/urandom: cannot read random bytes");
  return raw;
}

}  // namespace lmcfg::serve
