// The drive client against the manual's own conversations: each request must
// be byte-identical to the manual's Tx line and each answer is the manual's
// Rx line (seed 003; seed line numbers in tests/golden/seed003-captures.txt).
#include <catch2/catch.hpp>

#include "client/client.hpp"
#include "common/layers.hpp"
#include "manual_client.hpp"

// This file's own namespace: the test binary is a unity build (tests/CMakeLists.txt).
namespace client_test_client_manual {

using namespace lmcfg;
using namespace lmcfg::client;

using Fixture = test::ManualClient;

TEST_CASE("seed003 §9.1 read RAM value of 13A2h", "[client][golden]") {
  Fixture f(756, 758);
  auto v = f.client.read_ram(0x13A2);
  REQUIRE(v.ok());
  CHECK(*v == 0x0A);
  f.done();
}

TEST_CASE("seed003 §10.1 ROM read/write, type, min, max, default of 13A2h", "[client][golden]") {
  Fixture f(926, 964);
  CHECK(f.client.read_rom(0x13A2).value() == 9);
  CHECK(f.client.write_rom(0x13A2, 16).ok());
  CHECK(f.client.read_rom(0x13A2).value() == 16);
  CHECK(f.client.get_type(0x13A2).value() == 0x03);
  CHECK(f.client.get_min(0x13A2).value() == 0);
  CHECK(f.client.get_max(0x13A2).value() == 0xFFFF);
  CHECK(f.client.get_default(0x13A2).value() == 15);
  f.done();
}

TEST_CASE("seed003 §10.4 defaulting each layer", "[client][golden]") {
  Fixture f(1079, 1101);
  for (int layer = 1; layer <= 4; ++layer) CHECK(f.client.default_layer(layer).ok());
  f.done();
}

TEST_CASE("seed003 §13.1 reset, §13.3 stop and §13.4 start with answers", "[client][golden]") {
  Fixture f(1839, 1841);
  CHECK(f.client.reset().ok());
  f.done();
  Fixture g(1891, 1893);
  CHECK(g.client.stop_mc().ok());
  g.done();
  Fixture h(1924, 1926);
  CHECK(h.client.start_mc().ok());
  h.done();
}

TEST_CASE("seed003 §14.3 error counters and §14.4 error log entry", "[client][golden]") {
  Fixture f(2088, 2090);
  auto c = f.client.error_counters();
  REQUIRE(c.ok());
  CHECK(c->logged == 0x15);
  CHECK(c->occurred == 0x90);
  f.done();
  Fixture g(2137, 2139);
  auto e = g.client.error_log_entry(0);
  REQUIRE(e.ok());
  CHECK(e->code == 0x0C);
  CHECK(e->millis ==
        921918);  // 000E113Eh; the manual prints "921218ms" beside it (typo: 15 min 21.918 s)
  CHECK(e->hours == 623);
  g.done();
}

TEST_CASE("client: an error communication state becomes a typed refusal", "[client]") {
  test::ScriptedTransport link;
  // A C8 answer (unknown UPID) in the configuration group's response form.
  link.steps.push_back({*from_hex("01 11 05 02 00 05 34 12 04"),
                        *from_hex("01 11 0A 02 50 00 C8 34 12 00 00 00 00 04")});
  LinrsClient client(link, ClientOptions{});
  auto r = client.read_rom(0x1234);
  REQUIRE_FALSE(r.ok());
  CHECK(r.error().code == make_comm_state_error(0xC8));
  CHECK(r.error().message ==
        "drive 11h refused ID 11h parameter configuration (main 05h sub 00h), 2 data byte(s) for "
        "UPID 1234h: C8h parameter unknown UPID");
}

TEST_CASE("client: reads retry on silence, writes do not", "[client]") {
  test::ScriptedTransport link;
  const Bytes req = *from_hex("01 11 05 02 00 05 A2 13 04");
  link.steps.push_back({req, {}});  // lost answer
  link.steps.push_back(
      {req, *from_hex("01 11 0A 02 50 00 00 A2 13 09 00 00 00 04")});  // retry succeeds
  ClientOptions o;
  o.timeout = Millis(5);
  LinrsClient client(link, o);
  auto v = client.read_rom(0x13A2);
  REQUIRE(v.ok());
  CHECK(*v == 9);
  CHECK(client.stats().retries == 1);

  test::ScriptedTransport wlink;
  wlink.steps.push_back({*from_hex("01 11 09 02 01 05 A2 13 10 00 00 00 04"), {}});
  LinrsClient writer(wlink, o);
  auto w = writer.write_rom(0x13A2, 16);
  REQUIRE_FALSE(w.ok());
  CHECK(w.error().code == Errc::timeout);
  CHECK(w.error().message ==
        "no answer from drive 11h within 5 ms to ID 11h parameter configuration (main 05h sub "
        "01h), 6 data byte(s)");
  CHECK(writer.stats().requests == 1);
}

}  // namespace client_test_client_manual
