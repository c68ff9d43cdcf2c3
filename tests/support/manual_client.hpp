#pragma once
// A client talking to the manual's own conversation (seed 003 lines `from`..`to`
// of tests/golden/seed003-captures.txt): each request must be the manual's Tx
// line, each answer is its Rx line. done() checks that every step was used.
#include <catch2/catch.hpp>

#include "client/client.hpp"
#include "scripted_transport.hpp"

namespace lmcfg::test {

struct ManualClient {
  ScriptedTransport link;
  client::LinrsClient client{link, client::ClientOptions{}};
  explicit ManualClient(int from, int to) { link.steps = manual_steps(from, to); }
  void done() {
    CHECK(link.mismatches.empty());
    for (auto& m : link.mismatches) UNSCOPED_INFO(m);
    CHECK(link.steps.empty());
  }
};

}  // namespace lmcfg::test
