// UDP datagrams (lib/transport/udp.*): one write is one datagram, one
// read_some one datagram whole; two sockets share the LinUDP master port
// 41136 (LinUDP V2 §4.3) and each gets its own peer's replies.
#include <catch2/catch.hpp>

#include "transport/udp.hpp"

// This file's own namespace: the test binary is a unity build (tests/CMakeLists.txt).
namespace transport_test_udp {

using namespace lmcfg;
using namespace lmcfg::transport;

namespace {
Bytes b(std::initializer_list<int> v) {
  Bytes out;
  for (int x : v) out.push_back(static_cast<std::uint8_t>(x));
  return out;
}
UdpServer::Datagram receive(UdpServer& s) {
  auto d = s.receive(Millis(2000));
  REQUIRE(d.ok());
  REQUIRE(d->has_value());
  return std::move(**d);
}
}  // namespace

TEST_CASE("udp: datagrams keep their boundaries both ways", "[transport][udp]") {
  auto server = UdpServer::bind("127.0.0.1", 0);
  REQUIRE(server.ok());
  REQUIRE(server->port() != 0);
  auto t = open_udp("127.0.0.1", server->port(), UdpOptions{0});
  REQUIRE(t.ok());
  CHECK((*t)->describe() == "udp 127.0.0.1:" + std::to_string(server->port()));
  REQUIRE((*t)->write(b({1, 2, 3})).ok());
  REQUIRE((*t)->write(b({4, 5})).ok());
  auto d1 = receive(*server);
  auto d2 = receive(*server);
  CHECK(d1.bytes == b({1, 2, 3}));
  CHECK(d2.bytes == b({4, 5}));
  REQUIRE(server->send_to(d1, b({9, 9})).ok());
  REQUIRE(server->send_to(d1, b({8})).ok());
  auto r1 = (*t)->read_some(Millis(2000));
  auto r2 = (*t)->read_some(Millis(2000));
  REQUIRE(r1.ok());
  REQUIRE(r2.ok());
  CHECK(*r1 == b({9, 9}));
  CHECK(*r2 == b({8}));
  auto none = (*t)->read_some(Millis(20));
  REQUIRE(none.ok());
  CHECK(none->empty());
}

TEST_CASE("udp: two links from the master port 41136 each hear their own drive",
          "[transport][udp]") {
  auto s1 = UdpServer::bind("127.0.0.1", 0);
  auto s2 = UdpServer::bind("127.0.0.1", 0);
  REQUIRE(s1.ok());
  REQUIRE(s2.ok());
  auto t1 = open_udp("127.0.0.1", s1->port());
  auto t2 = open_udp("127.0.0.1", s2->port());
  REQUIRE(t1.ok());
  REQUIRE(t2.ok());
  REQUIRE((*t1)->write(b({1})).ok());
  REQUIRE((*t2)->write(b({2})).ok());
  auto d1 = receive(*s1);
  auto d2 = receive(*s2);
  CHECK(d1.from_port == 41136);
  CHECK(d2.from_port == 41136);
  REQUIRE(s2->send_to(d2, b({22})).ok());
  REQUIRE(s1->send_to(d1, b({11})).ok());
  CHECK(*(*t1)->read_some(Millis(2000)) == b({11}));
  CHECK(*(*t2)->read_some(Millis(2000)) == b({22}));
}

TEST_CASE("udp: a name that does not resolve is said so", "[transport][udp]") {
  auto t = open_udp("no-such-host.invalid", 49360, UdpOptions{0});
  REQUIRE_FALSE(t.ok());
  CHECK(t.error().code == make_error_code(Errc::invalid_argument));
  CHECK(t.error().message.rfind(
            "udp no-such-host.invalid:49360: cannot resolve 'no-such-host.invalid'", 0) == 0);
}

}  // namespace transport_test_udp
