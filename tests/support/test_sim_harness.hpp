#pragma once
// Shared helpers of the tests/sim/test_sim_*.cpp files.
#include <catch2/catch.hpp>
#include <fstream>
#include <memory>
#include <set>
#include <sstream>
#include <string>

#include "codec/frame.hpp"
#include "codec/messages.hpp"
#include "e2e_support.hpp"  // sim_fixture
#include "sim/drive.hpp"
#include "sim/link.hpp"
#include "sim/state_file.hpp"

namespace lmcfg::test {

inline sim::DriveState load_fixture(const std::string& name) {
  auto s = sim::load_state(sim_fixture(name));
  if (!s.ok()) FAIL(s.error().message);
  return std::move(s).value();
}

struct SimHarness {
  std::shared_ptr<sim::Drive> drive;
  sim::SimLink link;

  explicit SimHarness(sim::DriveState s)
      : drive(std::make_shared<sim::Drive>(std::move(s))), link(drive) {}
  explicit SimHarness(const std::string& fixture) : SimHarness(load_fixture(fixture)) {}

  // One request, the answer bytes that arrive within `timeout_ms` (empty on timeout).
  Bytes exchange(ByteView request, int timeout_ms = 15000) {
    auto w = link.write(request);
    REQUIRE(w.ok());
    auto r = link.read_some(transport::Millis(timeout_ms));
    REQUIRE(r.ok());
    return std::move(r).value();
  }
  Bytes exchange(const codec::Telegram& t, int timeout_ms = 15000) {
    auto cfg = drive->state().checksum;
    auto b = codec::encode(t, cfg);
    REQUIRE(b.ok());
    return exchange(*b, timeout_ms);
  }
  // Exchange and decode the answer (must be one telegram).
  codec::Telegram ask(const codec::Telegram& t, int timeout_ms = 15000) {
    auto rx = exchange(t, timeout_ms);
    auto d = codec::decode(rx, drive->state().checksum);
    INFO("answer " << to_hex(rx));
    REQUIRE(d.ok());
    return std::move(d).value();
  }
  codec::IdValueResponse ask_iv(const codec::Telegram& t, std::uint8_t sub) {
    auto a = ask(t);
    INFO(codec::describe(a) << " data " << to_hex(a.data));
    REQUIRE(a.sub == sub);
    REQUIRE(a.data.size() == 7);
    return {a.id, a.sub, a.data[0], get_u16le(a.data, 1), get_u32le(a.data, 3)};
  }
  // Wait on the virtual clock (e.g. for a reboot to complete).
  void idle(int ms) { (void)link.read_some(transport::Millis(ms)); }
};

inline std::set<int> seed003_inconsistent_lines() {
  std::ifstream in(std::string(LMCFG_SOURCE_DIR) + "/tests/golden/seed003-inconsistent.txt");
  std::set<int> out;
  std::string line;
  while (std::getline(in, line)) {
    if (line.empty() || line[0] == '#') continue;
    out.insert(std::stoi(line));
  }
  return out;
}

}  // namespace lmcfg::test
