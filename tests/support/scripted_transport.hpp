#pragma once
// A transport that plays a recorded conversation: each write must equal the
// next expected request, and is answered with the recorded response bytes.
#include <deque>
#include <string>

#include "common/bytes.hpp"
#include "golden_vectors.hpp"
#include "transport/transport.hpp"

namespace lmcfg::test {

class ScriptedTransport : public transport::Transport {
 public:
  struct Step {
    Bytes tx;
    Bytes rx;
  };
  std::deque<Step> steps;
  std::vector<std::string> mismatches;
  Bytes pending;

  Result<void> write(ByteView bytes) override {
    if (steps.empty()) {
      mismatches.push_back("unexpected request " + to_hex(bytes));
      return {};
    }
    Step s = steps.front();
    steps.pop_front();
    if (!std::equal(s.tx.begin(), s.tx.end(), bytes.begin(), bytes.end())) {
      mismatches.push_back("sent " + to_hex(bytes) + ", manual has " + to_hex(s.tx));
    }
    pending.insert(pending.end(), s.rx.begin(), s.rx.end());
    return {};
  }
  Result<Bytes> read_some(transport::Millis) override {
    Bytes out;
    out.swap(pending);
    return out;
  }
  void discard_input() override { pending.clear(); }
  std::string describe() const override { return "scripted"; }
};

// Tx/Rx pairs of the seed 003 captures between two seed lines (inclusive).
inline std::deque<ScriptedTransport::Step> manual_steps(int from_line, int to_line) {
  std::deque<ScriptedTransport::Step> out;
  for (const auto& c : load_seed003_captures()) {
    if (c.seed_line < from_line || c.seed_line > to_line) continue;
    if (c.tx) {
      out.push_back({c.bytes, {}});
    } else if (!out.empty() && out.back().rx.empty()) {
      out.back().rx = c.bytes;
    }
  }
  return out;
}

}  // namespace lmcfg::test
