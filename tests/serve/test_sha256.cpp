// SHA-256 (lib/serve/sha256.cpp): the FIPS 180-4 example digests, the
// published 896-bit vector, the raw digest's bytes, and every padding case
// (FIPS 180-4 §5.1.1: one or two final blocks) against coreutils sha256sum.
#include <catch2/catch.hpp>
#include <sstream>

#include "files.hpp"
#include "serve/sha256.hpp"
#include "subprocess.hpp"

// This file's own namespace: the test binary is a unity build (tests/CMakeLists.txt).
namespace serve_test_sha256 {

using namespace lmcfg;

TEST_CASE("serve: SHA-256 gives the FIPS 180-4 example digests (§B.1, §B.2, §B.3)",
          "[serve][sha256]") {
  // FIPS 180-4 / NIST examples: "abc" (one block), the 448-bit message (two
  // blocks), one million 'a'. The empty message is the well-known e3b0c442...
  CHECK(serve::sha256_hex("abc") ==
        "BA7816BF8F01CFEA414140DE5DAE2223B00361A396177A9CB410FF61F20015AD");
  CHECK(serve::sha256_hex("abcdbcdecdefdefgefghfghighijhijkijkljklmklmnlmnomnopnopq") ==
        "248D6A61D20638B8E5C026930C3E6039A33CE45964FF2167F6ECEDD419DB06C1");
  CHECK(serve::sha256_hex(std::string(1000000, 'a')) ==
        "CDC76E5C9914FB9281A1C7E284D73E67F1809A48A497200E046D39CCC7112CD0");
  CHECK(serve::sha256_hex("") ==
        "E3B0C44298FC1C149AFBF4C8996FB92427AE41E4649B934CA495991B7852B855");
}

TEST_CASE("sha256: the 896-bit example message (two full blocks of input, FIPS 180-4 §5.1.1)",
          "[serve][sha256]") {
  // The published SHA-256 vector of the 896-bit message that FIPS 180-4's
  // SHA-384/512 examples use: 112 bytes, so the padding needs a third block.
  CHECK(serve::sha256_hex("abcdefghbcdefghicdefghijdefghijkefghijklfghijklmghijklmnhijklmno"
                          "ijklmnopjklmnopqklmnopqrlmnopqrsmnopqrstnopqrstu") ==
        "CF5B16A778AF8380036CE59E7B0492370B249B11E8F07A51AFAC45037AFEE9D1");
}

TEST_CASE("sha256: the raw digest is the hash value H0..H7 big-endian (FIPS 180-4 §6.2.2 step 4)",
          "[serve][sha256]") {
  // "abc": H0 = ba7816bf ... H7 = f20015ad (FIPS 180-4 example, §B.1).
  const auto d = serve::sha256("abc");
  CHECK(d.size() == 32);
  CHECK(d[0] == 0xBA);
  CHECK(d[1] == 0x78);
  CHECK(d[2] == 0x16);
  CHECK(d[3] == 0xBF);
  CHECK(d[28] == 0xF2);
  CHECK(d[29] == 0x00);
  CHECK(d[30] == 0x15);
  CHECK(d[31] == 0xAD);
  // The hex form is those bytes, upper case, without separators.
  const std::string hex = serve::sha256_hex("abc");
  REQUIRE(hex.size() == 64);
  CHECK(hex.find_first_not_of("0123456789ABCDEF") == std::string::npos);
}

TEST_CASE("sha256: every message length from 0 to 200 bytes and binary bytes agree with sha256sum",
          "[serve][sha256]") {
  // Lengths 55/56 (the last one-block tail and the first two-block one), 63,
  // 64, 119/120, 127, 128 are the padding's edges; the bytes cover 00..FF so
  // an embedded NUL or a sign extension would show. The expected digests come
  // from coreutils, not from the code under test.
  test::ScratchDir d("sha256");
  std::vector<std::string> messages;
  std::string files;
  for (std::size_t n = 0; n <= 200; ++n) {
    std::string m(n, '\0');
    for (std::size_t i = 0; i < n; ++i) m[i] = static_cast<char>((i * 37 + n) & 0xFF);
    const auto path = d.path / ("m" + std::to_string(n));
    test::spit(path, m);
    messages.push_back(m);
    files += " '" + path.string() + "'";
  }
  std::istringstream out(test::shell_output("sha256sum" + files));
  std::string line;
  std::size_t n = 0;
  while (std::getline(out, line)) {
    REQUIRE(n < messages.size());
    REQUIRE(line.size() > 64);
    std::string expected = line.substr(0, 64);
    for (char& c : expected) c = static_cast<char>(std::toupper(static_cast<unsigned char>(c)));
    INFO("message of " << n << " bytes");
    CHECK(serve::sha256_hex(messages[n]) == expected);
    ++n;
  }
  CHECK(n == messages.size());
}

}  // namespace serve_test_sha256
