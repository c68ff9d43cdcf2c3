#pragma once
// Shared by the transport tests.
#include <catch2/catch.hpp>
#include <chrono>

#include "transport/pty.hpp"
#include "transport/transport.hpp"

namespace lmcfg::test {

// Reads until `want` bytes arrived or 3 s passed (at most 200 reads).
inline Bytes read_n(transport::Transport& t, std::size_t want) {
  using namespace std::chrono_literals;
  Bytes got;
  const auto deadline = transport::Clock::now() + 3s;
  for (int i = 0; i < 200 && got.size() < want && transport::Clock::now() < deadline; ++i) {
    auto r = t.read_some(100ms);
    REQUIRE(r.ok());
    got.insert(got.end(), r->begin(), r->end());
  }
  return got;
}

// A fresh pseudo-terminal pair (transport::open_pty), required to open.
inline transport::PtyPair make_pty() {
  auto p = transport::open_pty();
  REQUIRE(p.ok());
  return std::move(p).value();
}

}  // namespace lmcfg::test
