// The simulated slcan adapter (lib/sim/slcan_adapter.cpp, docs/can.md) served
// on one end of a socket pair, a client on the other: the Lawicel commands'
// answers, frames to and from the virtual bus only while the channel is open,
// and bus errors at a wrong bit rate.
#include <sys/socket.h>

#include <atomic>
#include <catch2/catch.hpp>
#include <chrono>
#include <thread>

#include "can/frame.hpp"
#include "can/virtual_bus.hpp"
#include "sim/slcan_adapter.hpp"
#include "transport/pty.hpp"

// This file's own namespace: the test binary is a unity build (tests/CMakeLists.txt).
namespace sim_test_slcan_adapter {

using namespace lmcfg;
using namespace std::chrono_literals;

namespace {

struct Rig {
  std::shared_ptr<can::VirtualBus> bus = std::make_shared<can::VirtualBus>();
  std::unique_ptr<transport::FdTransport> adapter_side, client;
  std::atomic<bool> stop{false};
  std::thread thread;
  Result<void> served;
  std::vector<can::Frame> heard;  // what the bus's node received

  explicit Rig(bool silent = false) {
    int fds[2];
    REQUIRE(::socketpair(AF_UNIX, SOCK_STREAM, 0, fds) == 0);
    adapter_side = std::make_unique<transport::FdTransport>(transport::UniqueFd(fds[0]), "adapter");
    client = std::make_unique<transport::FdTransport>(transport::UniqueFd(fds[1]), "client");
    // A node answering each frame with its identifier + 1 and the same data.
    bus->attach([this](const can::Frame& f, can::VirtualBus& b) {
      heard.push_back(f);
      can::Frame answer = f;
      answer.id = f.id + 1;
      b.put(answer);
    });
    sim::SlcanAdapterOptions opt;
    opt.poll = transport::Millis(5);
    opt.silent = silent;
    opt.should_stop = [this] { return stop.load(); };
    thread = std::thread([this, opt] { served = sim::serve_slcan(*bus, *adapter_side, opt); });
  }
  ~Rig() {
    stop = true;
    thread.join();
  }

  // Sends `line` and returns what the adapter answered, read until `want`
  // bytes came or 2 s passed.
  std::string say(const std::string& line, std::size_t want) {
    REQUIRE(client->write(as_bytes(line)).ok());
    std::string got;
    const auto deadline = transport::Clock::now() + 2s;
    while (got.size() < want && transport::Clock::now() < deadline) {
      auto r = client->read_some(transport::Millis(50));
      REQUIRE(r.ok());
      got.append(r->begin(), r->end());
    }
    // Nothing more than asked for.
    auto more = client->read_some(transport::Millis(30));
    REQUIRE(more.ok());
    got.append(more->begin(), more->end());
    return got;
  }
};

}  // namespace

TEST_CASE("sim slcan adapter: bit rate, open and close are acknowledged or refused with BEL",
          "[sim][slcan]") {
  Rig rig;
  CHECK(rig.say("t1232AABB\r", 1) == "\a");  // closed: no frame goes out
  CHECK(rig.say("S4\r", 1) == "\r");
  CHECK(rig.say("O\r", 1) == "\r");
  CHECK(rig.say("O\r", 1) == "\a");   // already open
  CHECK(rig.say("S5\r", 1) == "\a");  // no bit rate change while open
  CHECK(rig.say("C\r", 1) == "\r");
  CHECK(rig.say("C\r", 1) == "\a");  // already closed
  CHECK(rig.say("X\r", 1) == "\a");  // unknown command
  CHECK(rig.say("\r", 1) == "\r");   // an empty line
  CHECK(rig.heard.empty());
}

TEST_CASE("sim slcan adapter: an open channel at the bus's rate carries frames both ways",
          "[sim][slcan]") {
  Rig rig;
  CHECK(rig.say("S4\rO\r", 2) == "\r\r");
  // The transmit acknowledgement, then the node's answer as the adapter
  // reports a received frame.
  CHECK(rig.say("t1232AABB\r", 12) == "z\rt1242AABB\r");
  REQUIRE(rig.heard.size() == 1);
  const std::uint8_t ab[] = {0xAA, 0xBB};
  CHECK(rig.heard[0] == can::Frame::standard(0x123, ab));
  CHECK(rig.say("F\r", 4) == "F00\r");
}

TEST_CASE("sim slcan adapter: at another bit rate frames reach no node and the flags say bus error",
          "[sim][slcan]") {
  Rig rig;
  CHECK(rig.say("S5\rO\r", 2) == "\r\r");  // 250 kbit/s on a 125 kbit/s bus
  CHECK(rig.say("t1232AABB\r", 2) == "z\r");
  CHECK(rig.heard.empty());
  CHECK(rig.say("F\r", 4) == "FA0\r");
  CHECK(rig.say("F\r", 4) == "F00\r");  // reading the flags clears them
}

TEST_CASE("sim slcan adapter: V reports the version", "[sim][slcan]") {
  Rig rig;
  CHECK(rig.say("V\r", 6) == "V1013\r");
}

TEST_CASE(
    "sim slcan adapter: a silent adapter takes its commands and carries frames, "
    "answering nothing itself",
    "[sim][slcan]") {
  Rig rig(true);
  CHECK(rig.say("C\rV\rS4\rO\r", 0).empty());
  // No transmit acknowledgement: only the node's answer comes back.
  CHECK(rig.say("t1232AABB\r", 10) == "t1242AABB\r");
  REQUIRE(rig.heard.size() == 1);
  CHECK(rig.say("F\r", 0).empty());
  CHECK(rig.say("X\r", 0).empty());
}

}  // namespace sim_test_slcan_adapter
