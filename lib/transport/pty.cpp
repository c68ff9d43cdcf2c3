// Pseudo-terminal pairs for tests and for serving a simulated drive.
#include "transport/pty.hpp"

#include <errno.h>
#include <fcntl.h>
#include <pty.h>
#include <termios.h>
#include <unistd.h>

#include <array>
#include <cstring>

namespace lmcfg::transport {

namespace {
Error pty_error(const std::string& what, int err) {
  return Error(Errc::io_error, "pseudo-terminal: " + what + ": " + std::strerror(err));
}
bool set_cloexec(int fd) {
  const int fl = ::fcntl(fd, F_GETFD);
  return fl >= 0 && ::fcntl(fd, F_SETFD, fl | FD_CLOEXEC) == 0;
}
}  // namespace

Result<PtyPair> open_pty() {
  int m = -1;
  int s = -1;
  if (::openpty(&m, &s, nullptr, nullptr, nullptr) != 0) return pty_error("openpty failed", errno);
  PtyPair p;
  p.master.reset(m);
  p.slave.reset(s);
  if (!set_cloexec(m) || !set_cloexec(s)) return pty_error("cannot set close-on-exec", errno);

  std::array<char, 256> name{};
  if (const int rc = ::ttyname_r(s, name.data(), name.size()); rc != 0)
    return pty_error("cannot name the slave", rc);
  p.slave_path = name.data();

  // On Linux the master's termios calls act on the slave's line settings: raw
  // both ways (no echo, no CR/LF mapping, no signals), reads return at once.
  termios t{};
  if (::tcgetattr(m, &t) != 0) return pty_error("tcgetattr on the master failed", errno);
  ::cfmakeraw(&t);
  t.c_cc[VMIN] = 0;
  t.c_cc[VTIME] = 0;
  if (::tcsetattr(m, TCSANOW, &t) != 0) return pty_error("tcsetattr on the master failed", errno);

  const int fl = ::fcntl(m, F_GETFL);
  if (fl < 0 || ::fcntl(m, F_SETFL, fl | O_NONBLOCK) != 0)
    return pty_error("cannot make the master non-blocking", errno);
  return p;
}

}  // namespace lmcfg::transport
