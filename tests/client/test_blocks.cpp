// The client's block reads (lib/client/blocks.cpp: curves of LinRS §11, the
// command table of §12) against the manual's conversations.
#include <catch2/catch.hpp>

#include "client/client.hpp"
#include "common/layers.hpp"
#include "manual_client.hpp"

// This file's own namespace: the test binary is a unity build (tests/CMakeLists.txt).
namespace client_test_blocks {

using namespace lmcfg;
using namespace lmcfg::client;

using Fixture = test::ManualClient;

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

}  // namespace client_test_blocks
