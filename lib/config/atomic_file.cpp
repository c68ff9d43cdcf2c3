#include "config/atomic_file.hpp"

#include <fcntl.h>
#include <sys/stat.h>
#include <unistd.h>

#include <cerrno>
#include <cstdlib>
#include <cstring>
#include <vector>

#include "config/input_file.hpp"

namespace lmcfg::config {
namespace fs = std::filesystem;

namespace {
Error sys_error(const fs::path& p, std::string_view what, int err) {
  return Error(Errc::file_error, p.string() + ": " + std::string(what) + ": " + std::strerror(err));
}

bool write_all(int fd, std::string_view content) {
  const char* p = content.data();
  std::size_t left = content.size();
  while (left > 0) {
    ssize_t n = ::write(fd, p, left);
    if (n < 0) {
      if (errno == EINTR) continue;
      return false;
    }
    p += n;
    left -= static_cast<std::size_t>(n);
  }
  return true;
}
// The process's umask without changing it (umask(2) can only set it, and
// setting it back races with other threads creating files): the "Umask:"
// line of /proc/self/status (Linux 4.7 and later), else the usual 022.
mode_t current_umask() {
  int fd = ::open("/proc/self/status", O_RDONLY | O_CLOEXEC);
  if (fd < 0) return 022;
  char buf[4096];
  const ssize_t n = ::read(fd, buf, sizeof buf - 1);
  ::close(fd);
  if (n <= 0) return 022;
  buf[n] = '\0';
  const char* at = std::strstr(buf, "Umask:");
  if (!at) return 022;
  return static_cast<mode_t>(std::strtoul(at + 6, nullptr, 8) & 0777);
}
}  // namespace

Result<void> write_file_atomic(const fs::path& path, std::string_view content) {
  if (path.empty()) return Error(Errc::file_error, "empty output path; expected a file path");
  struct stat st {};
  // A new file gets what open(2) would give it (0666 less the umask: an
  // administrator's umask 077 keeps the archive and state private); a file
  // replaced keeps its mode. mkstemp alone would make every file 0600.
  mode_t mode = 0666 & ~current_umask();
  if (::stat(path.c_str(), &st) == 0) {
    if (S_ISDIR(st.st_mode))
      return Error(Errc::file_error, path.string() + ": is a directory; expected a file path");
    if (!S_ISREG(st.st_mode))
      return Error(Errc::file_error,
                   path.string() + ": is not a regular file; expected a file path");
    mode = st.st_mode & 07777;
  }
  fs::path dir = path.parent_path();
  if (dir.empty()) dir = ".";
  // Built by appending rather than `"." + name + ".tmp-XXXXXX"`: at -O2/-O3 GCC 12
  // reports a -Wrestrict false positive inside std::string's operator+(const
  // char*, string&&) (GCC bug 105651; fixed in later GCC releases), an error under -Werror.
  std::string tmp_name = ".";
  tmp_name += path.filename().string();
  tmp_name += ".tmp-XXXXXX";
  std::string tmpl = (dir / tmp_name).string();
  std::vector<char> name(tmpl.begin(), tmpl.end());
  name.push_back('\0');
  int fd = ::mkstemp(name.data());
  if (fd < 0) return sys_error(path, "cannot create a temporary file in " + dir.string(), errno);
  const fs::path tmp(name.data());
  auto fail = [&](std::string_view what) -> Result<void> {
    int err = errno;
    if (fd >= 0) ::close(fd);
    ::unlink(tmp.c_str());
    return sys_error(path, what, err);
  };
  if (::fchmod(fd, mode) != 0) return fail("cannot set permissions");
  if (!write_all(fd, content)) return fail("write failed");
  if (::fsync(fd) != 0) return fail("fsync failed");
  if (::close(fd) != 0) {
    fd = -1;
    return fail("close failed");
  }
  fd = -1;
  if (::rename(tmp.c_str(), path.c_str()) != 0) return fail("cannot replace the file");
  int dfd = ::open(dir.c_str(), O_RDONLY | O_DIRECTORY | O_CLOEXEC);
  if (dfd >= 0) {
    // The data is in place; a failing directory fsync is reported but the new file stays.
    int rc = ::fsync(dfd);
    int err = errno;
    ::close(dfd);
    if (rc != 0 && err != EINVAL) return sys_error(dir, "fsync of the directory failed", err);
  }
  return {};
}

Result<void> append_file(const fs::path& path, std::string_view line) {
  auto os_error = [&](const char* what) {
    return Error(Errc::file_error, path.string() + ": " + what + ": " + std::strerror(errno));
  };
  const int fd = ::open(path.c_str(), O_WRONLY | O_APPEND | O_CREAT | O_CLOEXEC, 0600);
  if (fd < 0) return os_error("cannot open");
  // One write(): an O_APPEND write is positioned at the end and written as one step.
  ssize_t n;
  do {
    n = ::write(fd, line.data(), line.size());
  } while (n < 0 && errno == EINTR);
  if (n < 0) {
    auto e = os_error("cannot write");
    ::close(fd);
    return e;
  }
  if (static_cast<std::size_t>(n) != line.size()) {
    ::close(fd);
    return Error(Errc::file_error, path.string() + ": short write (" + std::to_string(n) + " of " +
                                       std::to_string(line.size()) +
                                       " bytes; the file system is full?)");
  }
  if (::close(fd) != 0) return os_error("cannot close");
  return {};
}

namespace input_file {

int open(const fs::path& path) { return ::open(path.c_str(), O_RDONLY | O_CLOEXEC); }
int standard_input() { return 0; }
long long regular_size(int fd) {
  struct stat st {};
  return ::fstat(fd, &st) == 0 && S_ISREG(st.st_mode) ? static_cast<long long>(st.st_size) : -1;
}
long read(int fd, char* buf, std::size_t n) {
  for (;;) {
    const ssize_t got = ::read(fd, buf, n);
    if (got >= 0 || errno != EINTR) return static_cast<long>(got);
  }
}
void close(int fd) { ::close(fd); }

}  // namespace input_file

}  // namespace lmcfg::config
