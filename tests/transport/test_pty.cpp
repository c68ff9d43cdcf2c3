// Pseudo-terminal pairs (lib/transport/pty.cpp): both ends raw and
// close-on-exec, the master non-blocking, the slave named for open_serial.
#include <fcntl.h>
#include <termios.h>
#include <unistd.h>

#include <catch2/catch.hpp>
#include <chrono>

#include "transport/pty.hpp"
#include "transport/transport.hpp"
#include "transport_test_support.hpp"

// This file's own namespace: the test binary is a unity build (tests/CMakeLists.txt).
namespace transport_test_pty {

using namespace lmcfg;
using namespace lmcfg::transport;
using namespace std::chrono_literals;
using test::make_pty;

TEST_CASE("pty: both ends close-on-exec, only the master non-blocking", "[transport][pty]") {
  auto pty = make_pty();
  CHECK((::fcntl(pty.master.get(), F_GETFD) & FD_CLOEXEC) != 0);
  CHECK((::fcntl(pty.slave.get(), F_GETFD) & FD_CLOEXEC) != 0);
  CHECK((::fcntl(pty.master.get(), F_GETFL) & O_NONBLOCK) != 0);
  CHECK((::fcntl(pty.slave.get(), F_GETFL) & O_NONBLOCK) == 0);
  CHECK(::isatty(pty.slave.get()) == 1);
  CHECK(is_pty_slave(pty.slave.get()));
  char name[256] = {};
  REQUIRE(::ttyname_r(pty.slave.get(), name, sizeof name) == 0);
  CHECK(pty.slave_path == name);
}

TEST_CASE("pty: every byte value crosses unchanged both ways, no echo, no CR/LF mapping",
          "[transport][pty]") {
  auto pty = make_pty();
  FdTransport master(std::move(pty.master), "pty master");
  FdTransport slave(std::move(pty.slave), "pty slave");
  Bytes all;
  for (unsigned i = 0; i < 256; ++i) all.push_back(static_cast<std::uint8_t>(i));
  REQUIRE(master.write(all).ok());
  CHECK(test::read_n(slave, all.size()) == all);
  const Bytes crlf{'\r', '\n', 0x03, 0x1A, 0x7F};
  REQUIRE(slave.write(crlf).ok());
  CHECK(test::read_n(master, crlf.size()) == crlf);
  auto echo = master.read_some(50ms);  // nothing the slave read came back
  REQUIRE(echo.ok());
  CHECK(echo->empty());
}

TEST_CASE("pty: two pairs have distinct slave paths", "[transport][pty]") {
  auto a = make_pty();
  auto b = make_pty();
  CHECK(a.slave_path != b.slave_path);
  CHECK(a.master.get() != b.master.get());
}

TEST_CASE("open_pty gives a raw master and a named slave", "[transport]") {
  auto pty = make_pty();
  CHECK(pty.master.valid());
  CHECK(pty.slave.valid());
  CHECK(pty.slave_path.rfind("/dev/pts/", 0) == 0);
  termios t{};
  REQUIRE(::tcgetattr(pty.slave.get(), &t) == 0);
  CHECK((t.c_lflag & (ICANON | ECHO | ISIG)) == 0);
  CHECK((t.c_oflag & OPOST) == 0);
}

}  // namespace transport_test_pty
