// The in-process CAN bus (lib/can/virtual_bus.cpp): what an endpoint sends
// reaches every other endpoint and every node, in order; nodes answer inside
// the send; a frame out of range never reaches the bus.
#include <catch2/catch.hpp>

#include "can/virtual_bus.hpp"

// This file's own namespace: the test binary is a unity build (tests/CMakeLists.txt).
namespace can_test_virtual_bus {

using namespace lmcfg;

namespace {

can::Frame frame(std::uint32_t id, std::vector<std::uint8_t> data) {
  return can::Frame::standard(id, ByteView(data.data(), data.size()));
}

std::optional<can::Frame> next(can::Link& l) {
  auto r = l.receive(transport::Millis(0));
  REQUIRE(r.ok());
  return *r;
}

}  // namespace

TEST_CASE("virtual bus: every endpoint but the sender receives each frame, in order",
          "[can][virtual_bus]") {
  auto bus = std::make_shared<can::VirtualBus>();
  auto a = bus->open("a");
  auto b = bus->open("b");
  auto c = bus->open("c");
  CHECK(a->describe() == "virtual CAN a");
  REQUIRE(a->send(frame(0x100, {1})).ok());
  REQUIRE(a->send(frame(0x101, {2, 3})).ok());
  CHECK_FALSE(next(*a));
  for (auto* l : {b.get(), c.get()}) {
    CHECK(next(*l) == frame(0x100, {1}));
    CHECK(next(*l) == frame(0x101, {2, 3}));
    CHECK_FALSE(next(*l));
  }
  CHECK(bus->frames() == 2);
}

TEST_CASE("virtual bus: a node sees the endpoints' frames and answers inside the send",
          "[can][virtual_bus]") {
  auto bus = std::make_shared<can::VirtualBus>();
  std::vector<can::Frame> seen;
  bus->attach([&](const can::Frame& f, can::VirtualBus& b) {
    seen.push_back(f);
    can::Frame answer = f;
    answer.id = f.id + 1;
    b.put(answer);
  });
  auto a = bus->open("a");
  auto b = bus->open("b");
  REQUIRE(a->send(frame(0x42E, {0x00, 0x4B})).ok());
  // The node heard the request only: its own answer (from no endpoint) is
  // not given back to nodes.
  CHECK(seen == std::vector<can::Frame>{frame(0x42E, {0x00, 0x4B})});
  // The sender gets the answer; the other endpoint gets request and answer.
  CHECK(next(*a) == frame(0x42F, {0x00, 0x4B}));
  CHECK_FALSE(next(*a));
  CHECK(next(*b) == frame(0x42E, {0x00, 0x4B}));
  CHECK(next(*b) == frame(0x42F, {0x00, 0x4B}));
  CHECK(bus->frames() == 2);
}

TEST_CASE("virtual bus: a frame out of range is refused and never put on the bus",
          "[can][virtual_bus]") {
  auto bus = std::make_shared<can::VirtualBus>();
  auto a = bus->open("a");
  auto b = bus->open("b");
  can::Frame bad;
  bad.id = 0x800;
  auto sent = a->send(bad);
  REQUIRE_FALSE(sent.ok());
  CHECK(sent.error().message == "CAN identifier 800h does not fit 11 bits");
  CHECK(bus->frames() == 0);
  CHECK_FALSE(next(*b));
}

TEST_CASE("virtual bus: a closed endpoint receives nothing more", "[can][virtual_bus]") {
  auto bus = std::make_shared<can::VirtualBus>();
  auto a = bus->open("a");
  {
    auto b = bus->open("b");
    REQUIRE(a->send(frame(0x10, {})).ok());
  }
  auto c = bus->open("c");
  REQUIRE(a->send(frame(0x11, {})).ok());
  CHECK(next(*c) == frame(0x11, {}));
  CHECK_FALSE(next(*c));
  CHECK(bus->frames() == 2);
}

}  // namespace can_test_virtual_bus
