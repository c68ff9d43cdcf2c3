// The simulator's TCP listener (lib/sim/server_tcp.cpp, server_tcp_win32.cpp)
// with the TCP client (transport::open_tcp) and FdTransport on both ends:
// portable, so the Windows build runs it under Wine (Winsock) too.
#include <catch2/catch.hpp>
#include <chrono>

#include "sim/server.hpp"
#include "transport/pty.hpp"
#include "transport/transport.hpp"

// This file's own namespace: the test binary is a unity build (tests/CMakeLists.txt).
namespace sim_test_server_tcp {

using namespace lmcfg;
using transport::Millis;

// Reads until `n` bytes came or 2 s passed.
Bytes read_n(transport::Transport& t, std::size_t n) {
  Bytes got;
  const auto until = std::chrono::steady_clock::now() + std::chrono::seconds(2);
  while (got.size() < n && std::chrono::steady_clock::now() < until) {
    auto r = t.read_some(Millis(200));
    REQUIRE(r.ok());
    got.insert(got.end(), r->begin(), r->end());
  }
  return got;
}

TEST_CASE("sim tcp listener: a tcp client and the accepted socket move bytes both ways",
          "[sim][tcp]") {
  std::uint16_t port = 0;
  auto listener = sim::listen_tcp("127.0.0.1", 0, port);
  REQUIRE(listener.ok());
  REQUIRE(port != 0);
  auto client = transport::open_tcp("127.0.0.1", port, Millis(2000));
  REQUIRE(client.ok());
  CHECK((*client)->describe() == "tcp 127.0.0.1:" + std::to_string(port));
  auto accepted = sim::accept_client(listener->get(), Millis(2000));
  REQUIRE(accepted.ok());
  REQUIRE(accepted->valid());
  transport::FdTransport server(std::move(accepted).value(), "tcp client of lmcfg sim");

  const Bytes request{0x01, 0x11, 0x05, 0x02, 0x00, 0xFF, 0x04};
  REQUIRE((*client)->write(request).ok());
  CHECK(read_n(server, request.size()) == request);
  const Bytes answer{0x01, 0x00, 0xFF, 0x04};
  REQUIRE(server.write(answer).ok());
  CHECK(read_n(**client, answer.size()) == answer);

  // Nothing to read: an empty result once the deadline passed, not before.
  const auto t0 = std::chrono::steady_clock::now();
  auto idle = (*client)->read_some(Millis(60));
  const auto waited = std::chrono::steady_clock::now() - t0;
  REQUIRE(idle.ok());
  CHECK(idle->empty());
  CHECK(waited >= Millis(55));
  CHECK(waited < Millis(1500));

  server.close();
  auto closed = (*client)->read_some(Millis(2000));
  REQUIRE_FALSE(closed.ok());
  CHECK(closed.error().code == make_error_code(Errc::link_closed));
  CHECK(closed.error().message ==
        "tcp 127.0.0.1:" + std::to_string(port) + ": peer closed the connection");
}

TEST_CASE("sim tcp listener: no client within the wait, a closed port, a bad address",
          "[sim][tcp]") {
  std::uint16_t port = 0;
  {
    auto listener = sim::listen_tcp("127.0.0.1", 0, port);
    REQUIRE(listener.ok());
    auto none = sim::accept_client(listener->get(), Millis(50));
    REQUIRE(none.ok());
    CHECK_FALSE(none->valid());
  }
  // The listener is closed: the port refuses (the reason is the system's text).
  auto refused = transport::open_tcp("127.0.0.1", port, Millis(2000));
  REQUIRE_FALSE(refused.ok());
  CHECK(refused.error().code == make_error_code(Errc::io_error));
  const std::string prefix = "tcp 127.0.0.1:" + std::to_string(port) + ": cannot connect: ";
  CHECK(refused.error().message.rfind(prefix, 0) == 0);

  std::uint16_t unused = 0;
  auto bad = sim::listen_tcp("localhost", 0, unused);
  REQUIRE_FALSE(bad.ok());
  CHECK(bad.error().code == make_error_code(Errc::invalid_argument));
  CHECK(bad.error().message == "listen address 'localhost' is not an IPv4 address");
}

}  // namespace sim_test_server_tcp
