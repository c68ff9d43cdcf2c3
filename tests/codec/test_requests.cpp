// The request table (lib/codec/requests.cpp): which requests seed 003 defines,
// what each carries and which answer sub ID and key it draws, checked against
// every captured exchange of the manual.
#include <catch2/catch.hpp>
#include <cstdio>

#include "codec/frame.hpp"
#include "codec/requests.hpp"
#include "golden_vectors.hpp"

// This file's own namespace: the test binary is a unity build (tests/CMakeLists.txt).
namespace codec_test_requests {

using namespace lmcfg;
using namespace lmcfg::codec;

TEST_CASE("seed003 all captured exchanges: the request table names the answer's sub ID and key",
          "[codec][golden]") {
  // Every Tx directly followed by its Rx in the manual: the request exists in
  // the table, carries what the table says, and the drive's answer has the sub
  // ID the table expects and echoes the key the table says it echoes.
  const auto captures = test::load_seed003_captures();
  const auto inconsistent = test::load_seed003_inconsistent();
  int pairs = 0, keyed = 0, writes = 0;
  for (std::size_t i = 0; i + 1 < captures.size(); ++i) {
    const auto& tx = captures[i];
    const auto& rx = captures[i + 1];
    if (!tx.tx || rx.tx || rx.section != tx.section || inconsistent.count(rx.seed_line)) continue;
    INFO(tx.name() << ": " << to_hex(tx.bytes) << " -> " << to_hex(rx.bytes));
    auto req = decode(tx.bytes);
    auto ans = decode(rx.bytes);
    REQUIRE(req.ok());
    REQUIRE(ans.ok());
    const auto spec = request_spec(req->main, req->sub);
    REQUIRE(spec.has_value());
    CHECK(req->data.size() >= spec->data_len);
    CHECK(ans->sub == spec->answer_sub);
    if (spec->keyed && ans->data.size() >= 3) {
      CHECK(request_key(*req) == static_cast<std::uint16_t>(ans->data[1] | ans->data[2] << 8));
      ++keyed;
    }
    writes += spec->writes ? 1 : 0;
    ++pairs;
  }
  std::printf("seed003 exchanges checked against the request table: %d (%d keyed, %d writes)\n",
              pairs, keyed, writes);
  CHECK(pairs > 100);
}

TEST_CASE("request table: sub IDs the manual does not list are unknown, main IDs above 08h too",
          "[codec]") {
  CHECK_FALSE(request_spec(0x05, 0x02).has_value());  // §10 skips 02h/03h
  // 03h is LinRS 3V27 p27's address-usage read (a later manual), answered 53h.
  CHECK(request_spec(0x05, 0x03)->answer_sub == 0x53);
  CHECK(request_spec(0x05, 0x03)->keyed);
  CHECK_FALSE(request_spec(0x05, 0x10).has_value());
  CHECK_FALSE(request_spec(0x04, 0x03).has_value());  // §11 skips 03h and 07h
  CHECK_FALSE(request_spec(0x08, 0x08).has_value());
  CHECK_FALSE(request_spec(0x00, 0x00).has_value());  // §6 requests are 01h..04h
  CHECK(request_spec(0x03, 0x12).has_value());        // §9 default layer MC
  CHECK_FALSE(known_main(0x09));
  CHECK(known_main(0x08));
  CHECK(request_spec(0x06, 0x01)->answer_sub == 0x60);  // §13 reset after completion
  CHECK(request_spec(0x06, 0x02)->answer_sub == 0x00);  // immediate: default response
}

}  // namespace codec_test_requests
