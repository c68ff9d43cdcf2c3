// The frame and stream decoder (lib/codec/frame.*) on their own, with the
// captures of seed 003 (tests/golden/seed003-captures.txt; the ones that lost
// bytes in the manual are in seed003-inconsistent.txt).
#include <catch2/catch.hpp>
#include <map>
#include <string>

#include "codec/frame.hpp"
#include "golden_vectors.hpp"

// This file's own namespace: the test binary is a unity build (tests/CMakeLists.txt).
namespace codec_test_frame {

using namespace lmcfg;
using namespace lmcfg::codec;

namespace {

struct Split {
  std::vector<test::Capture> good, lost_bytes;
};

Split seed003_captures() {
  const auto bad = test::load_seed003_inconsistent();
  Split s;
  for (auto& c : test::load_seed003_captures())
    (bad.count(c.seed_line) ? s.lost_bytes : s.good).push_back(std::move(c));
  return s;
}

// Everything the decoder yields until it needs more input.
std::vector<Result<Telegram>> drain(StreamDecoder& d) {
  std::vector<Result<Telegram>> out;
  while (auto r = d.next()) out.push_back(std::move(*r));
  return out;
}

}  // namespace

TEST_CASE("stream decoder: every seed 003 capture, whole and byte by byte", "[codec][frame]") {
  const auto caps = seed003_captures();
  REQUIRE(caps.good.size() > 100);
  for (const auto& c : caps.good) {
    INFO(c.name());
    auto one = decode(c.bytes);
    REQUIRE(one.ok());
    StreamDecoder whole;
    whole.feed(c.bytes);
    auto r = whole.next();
    REQUIRE(r);
    REQUIRE(r->ok());
    CHECK(**r == *one);
    CHECK_FALSE(whole.next());
    CHECK(whole.buffered() == 0);
    CHECK(whole.garbage_bytes() == 0);

    StreamDecoder bytewise;
    for (std::size_t i = 0; i + 1 < c.bytes.size(); ++i) {
      bytewise.feed(ByteView(c.bytes).subspan(i, 1));
      CHECK_FALSE(bytewise.next());  // nothing before the end of telegram
    }
    bytewise.feed(ByteView(c.bytes).subspan(c.bytes.size() - 1));
    auto last = bytewise.next();
    REQUIRE(last);
    REQUIRE(last->ok());
    CHECK(**last == *one);
    CHECK_FALSE(bytewise.flush_idle());
  }
}

TEST_CASE("stream decoder: all captures back to back come out in order", "[codec][frame]") {
  const auto caps = seed003_captures();
  Bytes stream;
  for (const auto& c : caps.good) stream.insert(stream.end(), c.bytes.begin(), c.bytes.end());
  StreamDecoder d;
  d.feed(stream);
  const auto out = drain(d);
  REQUIRE(out.size() == caps.good.size());
  for (std::size_t i = 0; i < out.size(); ++i) {
    INFO(caps.good[i].name());
    REQUIRE(out[i].ok());
    CHECK(*out[i] == decode(caps.good[i].bytes).value());
  }
  CHECK(d.garbage_bytes() == 0);
}

TEST_CASE("stream decoder: garbage before a telegram is skipped and reported", "[codec][frame]") {
  const auto caps = seed003_captures();
  const auto& c = caps.good.front();  // LinRS §5.1
  StreamDecoder d;
  d.feed(Bytes{0xFF, 0x00, 0x55});
  d.feed(c.bytes);
  const auto out = drain(d);
  REQUIRE(out.size() == 2);
  REQUIRE_FALSE(out[0].ok());
  CHECK(out[0].error().code == Errc::frame_malformed);
  CHECK(d.garbage_bytes() == 3);
  REQUIRE(out[1].ok());
  CHECK(*out[1] == decode(c.bytes).value());
}

TEST_CASE("stream decoder: a start byte that cannot begin a telegram is dropped",
          "[codec][frame]") {
  const auto caps = seed003_captures();
  const auto& c = caps.good.front();
  for (const Bytes& bad : {Bytes{0x01, 0x11, 0x40, 0x02},     // LEN above 3Fh
                           Bytes{0x01, 0x11, 0x02, 0x02},     // LEN below 03h
                           Bytes{0x01, 0x11, 0x05, 0x03}}) {  // no start data 02h
    INFO(to_hex(bad));
    StreamDecoder d;
    d.feed(bad);
    d.feed(c.bytes);
    const auto out = drain(d);
    REQUIRE(out.size() >= 2);
    for (std::size_t i = 0; i + 1 < out.size(); ++i) {
      REQUIRE_FALSE(out[i].ok());
      CHECK(out[i].error().code == Errc::frame_malformed);
    }
    REQUIRE(out.back().ok());
    CHECK(*out.back() == decode(c.bytes).value());
    CHECK(d.garbage_bytes() == bad.size());
  }
}

TEST_CASE("stream decoder: the manual's captures that lost bytes", "[codec][frame]") {
  const auto caps = seed003_captures();
  REQUIRE_FALSE(caps.lost_bytes.empty());
  const auto& next_good = caps.good.front();
  for (const auto& c : caps.lost_bytes) {
    INFO(c.name());
    CHECK(decode(c.bytes).error().code == Errc::frame_short);
    // Alone, the decoder waits for the rest; when the line goes idle it is a
    // short telegram, and nothing of it stays.
    StreamDecoder alone;
    alone.feed(c.bytes);
    CHECK(drain(alone).empty());
    auto idle = alone.flush_idle();
    REQUIRE(idle);
    CHECK(idle->code == Errc::frame_short);
    CHECK(alone.buffered() == 0);
    CHECK(alone.garbage_bytes() == c.bytes.size());
    // Followed by a telegram: the short one swallows its first bytes, the
    // decoder finds no end of telegram where LEN puts it, resynchronises and
    // still finds the telegram after it.
    StreamDecoder then;
    then.feed(c.bytes);
    then.feed(next_good.bytes);
    const auto out = drain(then);
    REQUIRE(out.size() >= 2);
    REQUIRE_FALSE(out.front().ok());
    CHECK(out.front().error().code == Errc::frame_short);
    REQUIRE(out.back().ok());
    CHECK(*out.back() == decode(next_good.bytes).value());
  }
}

TEST_CASE("stream decoder: a checksum mismatch consumes the whole telegram", "[codec][frame]") {
  const ChecksumConfig crc{ChecksumMode::crc_ccitt, 0xFFFF, ChecksumCoverage::id_through_data};
  const auto caps = seed003_captures();
  const Telegram first = decode(caps.good[0].bytes).value();
  const Telegram second = decode(caps.good[1].bytes).value();
  Bytes bad = encode(first, crc).value();
  bad[bad.size() - 3] ^= 0x01;  // a checksum byte
  StreamDecoder d(crc);
  d.feed(bad);
  d.feed(encode(second, crc).value());
  const auto out = drain(d);
  REQUIRE(out.size() == 2);
  REQUIRE_FALSE(out[0].ok());
  CHECK(out[0].error().code == Errc::checksum_mismatch);
  REQUIRE(out[1].ok());
  CHECK(*out[1] == second);
  CHECK(d.garbage_bytes() == 0);
}

}  // namespace codec_test_frame
