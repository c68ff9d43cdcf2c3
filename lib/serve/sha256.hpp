#pragma once
// SHA-256 (FIPS 180-4 §6.2) for the service's bearer tokens: the tokens file
// stores only the hash of each token. Small and self-contained; tested with
// the FIPS 180-4 example vectors (tests/serve/test_sha256.cpp).
#include <array>
#include <cstdint>
#include <string>
#include <string_view>

namespace lmcfg::serve {

std::array<std::uint8_t, 32> sha256(std::string_view data);
// The digest as 64 upper-case hex digits (common/bytes to_hex).
std::string sha256_hex(std::string_view data);

}  // namespace lmcfg::serve
