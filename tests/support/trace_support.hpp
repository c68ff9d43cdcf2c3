#pragma once
// The requests of a --trace file ("<t> TX <hex>" lines), decoded: what a
// command really sent, for tests that count write telegrams.
#include <catch2/catch.hpp>
#include <filesystem>
#include <fstream>
#include <sstream>
#include <string>
#include <vector>

#include "client/client.hpp"
#include "codec/frame.hpp"
#include "common/bytes.hpp"

namespace lmcfg::test {

inline std::vector<codec::Telegram> traced_requests(const std::filesystem::path& trace) {
  std::ifstream in(trace);
  std::string line;
  codec::StreamDecoder dec;
  std::vector<codec::Telegram> out;
  while (std::getline(in, line)) {
    std::istringstream ls(line);
    std::string t, dir;
    ls >> t >> dir;
    if (dir != "TX") continue;
    std::string hex;
    std::getline(ls, hex);
    auto bytes = from_hex(hex);
    REQUIRE(bytes.has_value());
    dec.feed(*bytes);
    while (auto item = dec.next())
      if (item->ok()) out.push_back(item->value());
  }
  return out;
}

// Write telegrams among them (codec::is_write_request).
inline std::size_t traced_writes(const std::filesystem::path& trace) {
  std::size_t n = 0;
  for (const auto& t : traced_requests(trace)) n += codec::is_write_request(t) ? 1 : 0;
  return n;
}

}  // namespace lmcfg::test
