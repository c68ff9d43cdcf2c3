// The drive client against the manual's own conversations: each request must
// be byte-identical to the manual's Tx line and each answer is the manual's
// Rx line (seed 003; seed line numbers in tests/golden/seed003-captures.txt).
#include <catch2/catch.hpp>

#include "client/client.hpp"
#include "common/layers.hpp"
#include "scripted_transport.hpp"

using namespace lmcfg;
using namespace lmcfg::client;

namespace {
struct Fixture {
  test::ScriptedTransport link;
  Client client{link, ClientOptions{}};
  explicit Fixture(int from, int to) { link.steps = test::manual_steps(from, to); }
  void done() {
    CHECK(link.mismatches.empty());
    for (auto& m : link.mismatches) UNSCOPED_INFO(m);
    CHECK(link.steps.empty());
  }
};
}  // namespace

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

TEST_CASE("seed003 §10.2 modified list of the Intf layer ends with C6 carrying 20C7h",
          "[client][golden]") {
  Fixture f(991, 1002);
  auto list = f.client.modified_list(lmcfg::layers::kIntf);
  REQUIRE(list.ok());
  std::vector<ModifiedParam> want{
      {0x200E, 2}, {0x2012, 8}, {0x206C, 3}, {0x2076, 0x11}, {0x20C7, 1}};
  CHECK(*list == want);
  f.done();
}

TEST_CASE("seed003 §10.3 UPID list: the C6 answer repeats 2137h and counts once",
          "[client][golden]") {
  Fixture f(1057, 1067);
  auto list = f.client.upid_list(lmcfg::layers::kIntf);
  REQUIRE(list.ok());
  std::vector<UpidInfo> want{
      {0x2008, 0x000D, 0x0A}, {0x2136, 0x1001, 0x03}, {0x2137, 0x1001, 0x03}};
  CHECK(*list == want);
  f.done();
}

TEST_CASE("seed003 §10.4 defaulting each layer", "[client][golden]") {
  Fixture f(1079, 1101);
  for (int layer = 1; layer <= 4; ++layer) CHECK(f.client.default_layer(layer).ok());
  f.done();
}

TEST_CASE("seed003 §11.1 read curve 1 sizes and info block (SinRise)", "[client][golden]") {
  Fixture f(1245, 1321);  // the data-block transcript's first answer is truncated in the manual
  auto sizes = f.client.curve_sizes(1);
  REQUIRE(sizes.ok());
  REQUIRE(sizes->has_value());
  CHECK((*sizes)->info == 0x46);
  CHECK((*sizes)->data == 0x54);
  auto info = f.client.read_curve_info(1, 0x46);
  INFO((info.ok() ? std::string() : info.error().message));
  REQUIRE(info.ok());
  CHECK(info->size() == 70);
  CHECK(to_hex(ByteView(*info).first(16)) == "46 00 03 00 15 00 04 00 53 69 6E 52 69 73 65 00");
  CHECK(get_u32le(*info, 32) == 100000);
  f.done();
}

TEST_CASE("seed003 §12 defined-entry list: entries 1, 2, 4, 5, 6", "[client][golden]") {
  Fixture f(1669, 1684);
  auto entries = f.client.ct_defined_entries();
  REQUIRE(entries.ok());
  CHECK(*entries == std::vector<std::uint16_t>{1, 2, 4, 5, 6});
  f.done();
}

TEST_CASE("seed003 §12.1 read command table entry 2", "[client][golden]") {
  Fixture f(1688, 1722);
  auto e = f.client.read_ct_entry(2);
  REQUIRE(e.ok());
  CHECK(to_hex(*e) ==
        "01 A7 FF FF 00 01 40 42 0F 00 20 A1 07 00 40 0D 03 00 40 0D 03 00 00 00 00 00 00 00 00 00 "
        "00 00 00 00 00 "
        "00 00 00 55 6E 6E 61 6D 65 64 00 00 00 00 00 00 00 00 00 FF FF FF FF FF FF FF FF FF FF");
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
  Client client(link, ClientOptions{});
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
  Client client(link, o);
  auto v = client.read_rom(0x13A2);
  REQUIRE(v.ok());
  CHECK(*v == 9);
  CHECK(client.stats().retries == 1);

  test::ScriptedTransport wlink;
  wlink.steps.push_back({*from_hex("01 11 09 02 01 05 A2 13 10 00 00 00 04"), {}});
  Client writer(wlink, o);
  auto w = writer.write_rom(0x13A2, 16);
  REQUIRE_FALSE(w.ok());
  CHECK(w.error().code == Errc::timeout);
  CHECK(w.error().message ==
        "no answer from drive 11h within 5 ms to ID 11h parameter configuration (main 05h sub "
        "01h), 6 data byte(s)");
  CHECK(writer.stats().requests == 1);
}
