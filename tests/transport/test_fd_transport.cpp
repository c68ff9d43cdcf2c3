// FdTransport (lib/transport/fd_transport.cpp) over a pty master, a pipe and a
// socket pair: reads wait for the first byte and drain the rest, a closed
// peer is link_closed, writes wait for room at most their timeout, and every
// message starts with the transport's description.
#include <sys/socket.h>
#include <unistd.h>

#include <catch2/catch.hpp>
#include <chrono>
#include <thread>

#include "transport/pty.hpp"
#include "transport/transport.hpp"
#include "transport_test_support.hpp"

// This file's own namespace: the test binary is a unity build (tests/CMakeLists.txt).
namespace transport_test_fd_transport {

using namespace lmcfg;
using namespace lmcfg::transport;
using namespace std::chrono_literals;
using test::make_pty;

TEST_CASE("FdTransport: a read waits for the first byte, then drains what is there",
          "[transport][fd]") {
  int fds[2];
  REQUIRE(::socketpair(AF_UNIX, SOCK_STREAM, 0, fds) == 0);
  FdTransport a(UniqueFd{fds[0]}, "socket a", 86.8);
  FdTransport b(UniqueFd{fds[1]}, "socket b");
  CHECK(a.describe() == "socket a");
  CHECK(a.byte_time_us() == 86.8);
  CHECK(b.byte_time_us() == 0.0);
  const auto t0 = Clock::now();
  auto none = a.read_some(100ms);
  REQUIRE(none.ok());
  CHECK(none->empty());
  CHECK(Clock::now() - t0 >= 90ms);
  REQUIRE(b.write(Bytes{1, 2, 3}).ok());
  REQUIRE(b.write(Bytes{4, 5}).ok());
  std::this_thread::sleep_for(20ms);
  auto got = a.read_some(1000ms);
  REQUIRE(got.ok());
  CHECK(*got == Bytes{1, 2, 3, 4, 5});
}

TEST_CASE("FdTransport: discard_input drops what arrived, later bytes still come",
          "[transport][fd]") {
  int fds[2];
  REQUIRE(::pipe(fds) == 0);
  FdTransport reader(UniqueFd{fds[0]}, "pipe");
  UniqueFd writer(fds[1]);
  REQUIRE(::write(writer.get(), "\x01\x02\x03", 3) == 3);
  reader.discard_input();
  auto none = reader.read_some(20ms);
  REQUIRE(none.ok());
  CHECK(none->empty());
  REQUIRE(::write(writer.get(), "\x04", 1) == 1);
  CHECK(test::read_n(reader, 1) == Bytes{4});
}

TEST_CASE("FdTransport: end of file on a pipe and a closed socket peer are link_closed",
          "[transport][fd]") {
  {
    int fds[2];
    REQUIRE(::pipe(fds) == 0);
    FdTransport reader(UniqueFd{fds[0]}, "pipe r");
    ::close(fds[1]);
    auto r = reader.read_some(1000ms);
    REQUIRE_FALSE(r.ok());
    CHECK(r.error().code == Errc::link_closed);
    CHECK(r.error().message == "pipe r: device hung up");
  }
  {
    int fds[2];
    REQUIRE(::socketpair(AF_UNIX, SOCK_STREAM, 0, fds) == 0);
    FdTransport a(UniqueFd{fds[0]}, "socket a");
    ::close(fds[1]);
    // send(MSG_NOSIGNAL): the closed peer is an error, never SIGPIPE.
    auto w = a.write(Bytes{1});
    REQUIRE_FALSE(w.ok());
    CHECK(w.error().code == Errc::link_closed);
    CHECK(w.error().message == "socket a: write failed: Broken pipe");
  }
}

TEST_CASE("FdTransport: after close() every call is link_closed", "[transport][fd]") {
  auto pty = make_pty();
  FdTransport master(std::move(pty.master), "pty master");
  master.close();
  CHECK(master.fd() == -1);
  auto r = master.read_some(10ms);
  REQUIRE_FALSE(r.ok());
  CHECK(r.error().code == Errc::link_closed);
  CHECK(r.error().message == "pty master: link is closed");
  auto w = master.write(Bytes{1});
  REQUIRE_FALSE(w.ok());
  CHECK(w.error().code == Errc::link_closed);
  CHECK(w.error().message == "pty master: link is closed");
}

TEST_CASE("pty master sees link_closed once no slave is open", "[transport]") {
  auto pty = make_pty();
  FdTransport master(std::move(pty.master), "pty master");
  {
    auto serial = open_serial({pty.slave_path, 57600, Parity::none, 1});
    REQUIRE(serial.ok());
    pty.slave.reset();  // the serial transport is the only slave now
    auto r = master.read_some(50ms);
    REQUIRE(r.ok());
    CHECK(r->empty());
  }
  const auto t0 = Clock::now();
  auto r = master.read_some(3000ms);
  CHECK(Clock::now() - t0 < 1500ms);
  REQUIRE_FALSE(r.ok());
  CHECK(r.error().code == Errc::link_closed);
  CHECK(r.error().message.rfind("pty master: ", 0) == 0);
}

TEST_CASE("FdTransport write times out when nobody reads", "[transport]") {
  auto pty = make_pty();
  FdTransport master(std::move(pty.master), "pty master");
  master.set_write_timeout(200ms);
  const Bytes block(4096, 0x55);
  bool timed_out = false;
  const auto t0 = Clock::now();
  for (int i = 0; i < 256 && !timed_out; ++i) {  // the pty buffer is far below 1 MiB
    auto w = master.write(block);
    if (!w.ok()) {
      CHECK(w.error().code == Errc::timeout);
      CHECK(w.error().message.rfind("pty master: write timed out after 200 ms", 0) == 0);
      timed_out = true;
    }
  }
  CHECK(timed_out);
  CHECK(Clock::now() - t0 < 5s);
}

}  // namespace transport_test_fd_transport
