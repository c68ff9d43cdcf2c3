// Checksum variants the manual leaves open (LinRS §4.4, §15 "Checksum":
// "Add" and "CRC CCITT polynomial 16 bit", neither the covered bytes nor the
// CRC's initial value / bit order settled). The expected values do not come
// from the code under test: the CRC check values ("123456789") are the
// published ones of the CRC catalogue (CRC-16/CCITT-FALSE 29B1h, XMODEM 31C3h,
// KERMIT 2189h); the framed vectors append to the manual's §9.1 capture the
// checksum computed by Python's binascii.crc_hqx (MSB-first CCITT with the
// given initial value), a byte sum, and a bit-by-bit reflected CRC.
#include <catch2/catch.hpp>
#include <cstring>

#include "codec/frame.hpp"
#include "codec/messages.hpp"
#include "link/session.hpp"

// This file's own namespace: the test binary is a unity build (tests/CMakeLists.txt).
namespace codec_test_codec_checksum {

using namespace lmcfg;
using namespace lmcfg::codec;

namespace {
Bytes ascii(const char* s) { return Bytes(s, s + std::strlen(s)); }

ChecksumConfig cfg(std::string_view name, std::string_view coverage) {
  auto c = link::parse_checksum(name).value();
  c.coverage = link::parse_checksum_coverage(coverage).value();
  return c;
}
}  // namespace

TEST_CASE("seed003 §4.4 checksum functions: published CRC-16 check values", "[codec][checksum]") {
  const Bytes check = ascii("123456789");
  CHECK(checksum_crc_ccitt(check, 0xFFFF) == 0x29B1);  // CRC-16/CCITT-FALSE
  CHECK(checksum_crc_ccitt(check, 0x0000) == 0x31C3);  // CRC-16/XMODEM
  CHECK(checksum_crc_kermit(check) == 0x2189);         // CRC-16/KERMIT
  CHECK(checksum_add(check) == 0x01DD);                // 477: byte sum mod 2^16
}

TEST_CASE("seed003 §9.1 read request framed with every checksum variant and coverage",
          "[codec][checksum]") {
  // Tx: 01 11 05 02 00 03 A2 13 04 (§9.1), checksum low/high before the 04.
  struct Vector {
    const char* mode;
    const char* coverage;
    std::uint16_t chk;
  };
  const Vector vectors[] = {
      {"add", "id", 0x00D0},        {"add", "start", 0x00D1},        {"add", "data", 0x00BA},
      {"crc-ffff", "id", 0x7948},   {"crc-ffff", "start", 0xFE6B},   {"crc-ffff", "data", 0x5591},
      {"crc-0000", "id", 0x8886},   {"crc-0000", "start", 0xCF55},   {"crc-0000", "data", 0x449D},
      {"crc-kermit", "id", 0x7922}, {"crc-kermit", "start", 0xF89D}, {"crc-kermit", "data", 0x47B9},
  };
  const Telegram req = make_param_read(0x11, ParamOp::read_ram, 0x13A2);
  for (const auto& v : vectors) {
    INFO(v.mode << " coverage " << v.coverage);
    const auto c = cfg(v.mode, v.coverage);
    Bytes want{0x01, 0x11, 0x05, 0x02, 0x00, 0x03, 0xA2, 0x13};
    want.push_back(static_cast<std::uint8_t>(v.chk & 0xFF));
    want.push_back(static_cast<std::uint8_t>(v.chk >> 8));
    want.push_back(0x04);
    CHECK(encode(req, c).value() == want);
    auto back = decode(want, c);
    REQUIRE(back.ok());
    CHECK(back.value() == req);
    // Every other variant rejects the frame as a checksum mismatch.
    for (const auto& other : vectors) {
      if (std::string_view(other.mode) == v.mode && std::string_view(other.coverage) == v.coverage)
        continue;
      if (other.chk == v.chk) continue;
      auto wrong = decode(want, cfg(other.mode, other.coverage));
      REQUIRE_FALSE(wrong.ok());
      CHECK(wrong.error().code == make_error_code(Errc::checksum_mismatch));
    }
  }
}

TEST_CASE("seed003 §15 checksum option names: existing ones stay accepted", "[codec][checksum]") {
  CHECK(link::parse_checksum("crc").value() == link::parse_checksum("crc-ffff").value());
  CHECK(link::checksum_name(link::parse_checksum("crc").value()) == "crc-ffff");
  CHECK(link::checksum_name(link::parse_checksum("crc-kermit").value()) == "crc-kermit");
  CHECK(link::checksum_options(cfg("crc-0000", "start")) ==
        "--checksum crc-0000 --checksum-coverage start");
  CHECK(link::checksum_options(cfg("none", "id")) == "--checksum none");
  CHECK(link::checksum_name(cfg("add", "data")) == "add coverage=data");
  auto bad = link::parse_checksum("crc16");
  REQUIRE_FALSE(bad.ok());
  CHECK(bad.error().message ==
        "checksum 'crc16' is not one of none, add, crc, crc-ffff, crc-0000, crc-kermit");
  auto badcov = link::parse_checksum_coverage("all");
  REQUIRE_FALSE(badcov.ok());
  CHECK(badcov.error().message == "checksum coverage 'all' is not one of id, start, data");
}

}  // namespace codec_test_codec_checksum
