#include "config/atomic_file.hpp"

#include <fcntl.h>
#include <sys/stat.h>
#include <unistd.h>

#include <cerrno>
#include <cstring>
#include <fstream>
#include <sstream>
#include <vector>

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
}  // namespace

Result<void> write_file_atomic(const fs::path& path, std::string_view content) {
  if (path.empty()) return Error(Errc::file_error, "empty output path; expected a file path");
  struct stat st {};
  mode_t mode = 0644;
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

Result<std::string> read_text_file(const fs::path& path) {
  std::error_code ec;
  if (fs::is_directory(path, ec))
    return Error(Errc::file_error, path.string() + ": is a directory; expected a file");
  std::ifstream in(path, std::ios::binary);
  if (!in) {
    if (!fs::exists(path, ec)) return Error(Errc::not_found, path.string() + ": no such file");
    return Error(Errc::file_error, path.string() + ": cannot open: " + std::strerror(errno));
  }
  std::ostringstream ss;
  ss << in.rdbuf();
  if (in.bad()) return Error(Errc::file_error, path.string() + ": read failed");
  return ss.str();
}

}  // namespace lmcfg::config
