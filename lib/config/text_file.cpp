// Reading an input file whole, bounded (atomic_file.hpp's read_text_file):
// the same on every platform; the calls that differ are input_file.hpp's.
#include <cerrno>
#include <cstdint>
#include <cstring>

#include "config/atomic_file.hpp"
#include "config/input_file.hpp"

namespace lmcfg::config {
namespace fs = std::filesystem;

std::string input_name(const fs::path& path) {
  return path == "-" ? std::string("(stdin)") : path.string();
}

namespace {
std::string mib(std::size_t n) {
  return n % (1u << 20) == 0 ? std::to_string(n >> 20) + " MiB" : std::to_string(n) + " bytes";
}

bool has_non_blank(std::string_view s) {
  for (char c : s)
    if (c != ' ' && c != '\t' && c != '\n' && c != '\r') return true;
  return false;
}
}  // namespace

Result<std::string> read_text_file(const fs::path& path, std::size_t max_bytes,
                                   HeadCheck check_head) {
  const std::string name = input_name(path);
  const bool is_stdin = path == "-";
  int fd = 0;
  if (is_stdin) {
    fd = input_file::standard_input();
  } else {
    std::error_code ec;
    if (fs::is_directory(path, ec))
      return Error(Errc::file_error, name + ": is a directory; expected a file");
    fd = input_file::open(path);
    if (fd < 0) {
      const int err = errno;
      if (err == ENOENT) return Error(Errc::not_found, name + ": no such file");
      return Error(Errc::file_error, name + ": cannot open: " + std::strerror(err));
    }
  }
  struct Closer {
    int fd;
    bool own;
    ~Closer() {
      if (own) input_file::close(fd);
    }
  } closer{fd, !is_stdin};
  const long long size = input_file::regular_size(fd);
  if (size >= 0 && static_cast<std::uint64_t>(size) > max_bytes)
    return Error(Errc::file_error, name + ": " + std::to_string(size) +
                                       " bytes, larger than any configuration (at most " +
                                       mib(max_bytes) + ")");
  std::string text;
  if (size > 0) text.reserve(static_cast<std::size_t>(size));
  bool head_checked = check_head == nullptr;
  char buf[65536];
  for (;;) {
    const long n = input_file::read(fd, buf, sizeof buf);
    if (n < 0) return Error(Errc::file_error, name + ": read failed: " + std::strerror(errno));
    if (n == 0) break;
    if (text.size() + static_cast<std::size_t>(n) > max_bytes)
      return Error(Errc::file_error, name + ": more than " + mib(max_bytes) +
                                         " (an endless stream?); a configuration is far smaller");
    text.append(buf, static_cast<std::size_t>(n));
    if (!head_checked && has_non_blank(std::string_view(buf, static_cast<std::size_t>(n)))) {
      head_checked = true;
      LMCFG_TRY(check_head(text, name));
    }
  }
  if (!head_checked) LMCFG_TRY(check_head(text, name));
  return text;
}

}  // namespace lmcfg::config
