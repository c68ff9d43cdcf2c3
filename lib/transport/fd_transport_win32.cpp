// Windows: UniqueFd holds a C runtime descriptor (the trace file). The
// descriptor transport is for pseudo-terminals and sockets, which this build
// does not offer yet (tcp_win32.cpp, pty_win32.cpp): its calls say so.
#include <io.h>

#include "transport/pty.hpp"

namespace lmcfg::transport {

namespace {

Error unavailable(const std::string& what) {
  return Error(Errc::not_supported, what +
                                        ": not available in the Windows build of lmcfg "
                                        "(docs/windows.md)");
}

}  // namespace

void UniqueFd::reset(int fd) noexcept {
  if (fd_ >= 0) ::_close(fd_);
  fd_ = fd;
}

FdTransport::FdTransport(UniqueFd fd, std::string description, double byte_time_us)
    : fd_(std::move(fd)), description_(std::move(description)), byte_time_us_(byte_time_us) {}

Error FdTransport::os_error(const char* what, int) const {
  return unavailable(description_ + ": " + what);
}

Result<void> FdTransport::write(ByteView) { return os_error("write", 0); }

Result<Bytes> FdTransport::read_some(Millis) { return os_error("read", 0); }

void FdTransport::discard_input() {}

}  // namespace lmcfg::transport
