// Windows: the same safe replacement as atomic_file.cpp with Win32 calls. The
// temporary file is written and flushed (FlushFileBuffers), then moved over
// the target with MoveFileExW(MOVEFILE_REPLACE_EXISTING |
// MOVEFILE_WRITE_THROUGH), which returns once the move is on the disk: the
// target is the old file or the new one, never a part. Paths are UTF-8 in
// lmcfg and UTF-16 for Windows (std::filesystem::path converts).
#ifndef WIN32_LEAN_AND_MEAN
#define WIN32_LEAN_AND_MEAN
#endif
#include <fcntl.h>
#include <io.h>
#include <sys/stat.h>
#include <sys/types.h>
#include <windows.h>

#include <cstdio>
#include <cstring>

#include "config/atomic_file.hpp"
#include "config/input_file.hpp"

namespace lmcfg::config {
namespace fs = std::filesystem;

namespace {

std::string win_error(DWORD err) {
  char buf[512] = {};
  const DWORD n = ::FormatMessageA(FORMAT_MESSAGE_FROM_SYSTEM | FORMAT_MESSAGE_IGNORE_INSERTS,
                                   nullptr, err, 0, buf, sizeof buf, nullptr);
  std::string s(buf, n);
  while (!s.empty() && (s.back() == '\n' || s.back() == '\r' || s.back() == '.')) s.pop_back();
  return s.empty() ? "Windows error " + std::to_string(err) : s;
}

Error sys_error(const fs::path& p, std::string_view what, DWORD err) {
  return Error(Errc::file_error, p.string() + ": " + std::string(what) + ": " + win_error(err));
}

struct Handle {
  HANDLE h;
  ~Handle() {
    if (h != INVALID_HANDLE_VALUE) ::CloseHandle(h);
  }
};

bool write_all(HANDLE h, std::string_view content) {
  const char* p = content.data();
  std::size_t left = content.size();
  while (left > 0) {
    DWORD n = 0;
    const DWORD chunk = static_cast<DWORD>(std::min<std::size_t>(left, 1u << 30));
    if (!::WriteFile(h, p, chunk, &n, nullptr) || n == 0) return false;
    p += n;
    left -= n;
  }
  return true;
}

}  // namespace

Result<void> write_file_atomic(const fs::path& path, std::string_view content) {
  // The checks and texts of atomic_file.cpp (the tests compare the messages).
  if (path.empty()) return Error(Errc::file_error, "empty output path; expected a file path");
  std::error_code ec;
  const auto type = fs::status(path, ec).type();
  if (type == fs::file_type::directory)
    return Error(Errc::file_error, path.string() + ": is a directory; expected a file path");
  if (type != fs::file_type::not_found && type != fs::file_type::none &&
      type != fs::file_type::regular)
    return Error(Errc::file_error, path.string() + ": is not a regular file; expected a file path");
  const fs::path dir = path.has_parent_path() ? path.parent_path() : fs::path(".");
  if (!fs::exists(dir, ec))
    return Error(Errc::file_error, path.string() + ": the folder " + dir.string() +
                                       " does not exist; create it or choose another path");
  // A name of our own next to the target (same volume: the move is a rename).
  fs::path tmp;
  HANDLE h = INVALID_HANDLE_VALUE;
  for (unsigned i = 0; i < 100 && h == INVALID_HANDLE_VALUE; ++i) {
    tmp = path;
    tmp += ".tmp." + std::to_string(::GetCurrentProcessId()) + "." + std::to_string(i);
    h = ::CreateFileW(tmp.c_str(), GENERIC_WRITE, 0, nullptr, CREATE_NEW, FILE_ATTRIBUTE_NORMAL,
                      nullptr);
    if (h == INVALID_HANDLE_VALUE && ::GetLastError() != ERROR_FILE_EXISTS)
      return sys_error(path, "cannot create a temporary file in " + dir.string(), ::GetLastError());
  }
  if (h == INVALID_HANDLE_VALUE)
    return Error(Errc::file_error, path.string() + ": cannot create a temporary file");
  auto fail = [&](std::string_view what, DWORD err) {
    if (h != INVALID_HANDLE_VALUE) ::CloseHandle(h);
    ::DeleteFileW(tmp.c_str());
    return sys_error(path, what, err);
  };
  if (!write_all(h, content)) return fail("write failed", ::GetLastError());
  if (!::FlushFileBuffers(h)) return fail("flush failed", ::GetLastError());
  ::CloseHandle(h);
  h = INVALID_HANDLE_VALUE;
  if (!::MoveFileExW(tmp.c_str(), path.c_str(), MOVEFILE_REPLACE_EXISTING | MOVEFILE_WRITE_THROUGH))
    return fail("cannot replace the file", ::GetLastError());
  return {};
}

Result<void> append_file(const fs::path& path, std::string_view line) {
  // FILE_APPEND_DATA without FILE_WRITE_DATA: every write goes to the end of
  // the file as one step (the Windows form of O_APPEND).
  Handle h{::CreateFileW(path.c_str(), FILE_APPEND_DATA, FILE_SHARE_READ | FILE_SHARE_WRITE,
                         nullptr, OPEN_ALWAYS, FILE_ATTRIBUTE_NORMAL, nullptr)};
  if (h.h == INVALID_HANDLE_VALUE) return sys_error(path, "cannot open", ::GetLastError());
  DWORD n = 0;
  if (!::WriteFile(h.h, line.data(), static_cast<DWORD>(line.size()), &n, nullptr))
    return sys_error(path, "cannot write", ::GetLastError());
  if (n != line.size())
    return Error(Errc::file_error, path.string() + ": short write (" + std::to_string(n) + " of " +
                                       std::to_string(line.size()) +
                                       " bytes; the file system is full?)");
  return {};
}

namespace input_file {

int open(const fs::path& path) { return ::_wopen(path.c_str(), _O_RDONLY | _O_BINARY); }
int standard_input() {
  ::_setmode(0, _O_BINARY);
  return 0;
}
long long regular_size(int fd) {
  struct _stat64 st {};
  return ::_fstat64(fd, &st) == 0 && (st.st_mode & _S_IFREG) != 0
             ? static_cast<long long>(st.st_size)
             : -1;
}
long read(int fd, char* buf, std::size_t n) {
  return ::_read(fd, buf, static_cast<unsigned>(std::min<std::size_t>(n, 1u << 30)));
}
void close(int fd) { ::_close(fd); }

}  // namespace input_file

}  // namespace lmcfg::config
