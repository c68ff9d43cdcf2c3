// Firmware layers and their UPID ranges (lib/common/layers.cpp). LinRS §10.2:
// "Each firmware layer has its own range of UPIDs for its parameters":
// 1 0000h...0EFFh Operating System, 2 1000h...1EFFh Motion Control SW,
// 3 2000h...2EFFh Interface Software, 4 3000h...3EFFh Application.
#include <catch2/catch.hpp>

#include "common/layers.hpp"

// This file's own namespace: the test binary is a unity build (tests/CMakeLists.txt).
namespace common_test_layers {

using namespace lmcfg;

TEST_CASE("LinRS §10.2 layers: each range's ends, the gaps between them and beyond",
          "[common][layers]") {
  CHECK(layers::of_upid(0x0000) == layers::kOS);
  CHECK(layers::of_upid(0x0EFF) == layers::kOS);
  CHECK(layers::of_upid(0x0F00) == 0);
  CHECK(layers::of_upid(0x0FFF) == 0);
  CHECK(layers::of_upid(0x1000) == layers::kMC);
  CHECK(layers::of_upid(0x13A2) == layers::kMC);  // §10.1's P Gain Position Controller Set A
  CHECK(layers::of_upid(0x1EFF) == layers::kMC);
  CHECK(layers::of_upid(0x1F00) == 0);
  CHECK(layers::of_upid(0x2000) == layers::kIntf);
  CHECK(layers::of_upid(0x20C7) == layers::kIntf);  // §10.2's last modified Intf UPID
  CHECK(layers::of_upid(0x2EFF) == layers::kIntf);
  CHECK(layers::of_upid(0x3000) == layers::kAppl);
  CHECK(layers::of_upid(0x3EFF) == layers::kAppl);
  CHECK(layers::of_upid(0x3F00) == 0);
  CHECK(layers::of_upid(0x4000) == 0);
  CHECK(layers::of_upid(0x6300) == 0);  // MC SW §3.7's UPID outside every range
  CHECK(layers::of_upid(0x10000) == 0);
  CHECK(layers::of_upid(0xFFFFFFFF) == 0);
}

TEST_CASE("LinRS §10.2 layers: base UPIDs of the modified-list start request, names",
          "[common][layers]") {
  CHECK(layers::kCount == 4);
  CHECK(layers::base_upid(layers::kOS) == 0x0000);
  CHECK(layers::base_upid(layers::kMC) == 0x1000);
  CHECK(layers::base_upid(layers::kIntf) == 0x2000);
  CHECK(layers::base_upid(layers::kAppl) == 0x3000);
  CHECK(layers::base_upid(0) == 0xFFFF);
  CHECK(layers::base_upid(5) == 0xFFFF);
  CHECK(layers::name(1) == "OS");
  CHECK(layers::name(2) == "MC");
  CHECK(layers::name(3) == "Intf");
  CHECK(layers::name(4) == "Appl");
  CHECK(layers::name(0) == "?");
  CHECK(layers::name(-1) == "?");
  for (int l = 1; l <= layers::kCount; ++l) {
    CHECK(layers::from_name(layers::name(l)) == std::optional<int>(l));
    CHECK(layers::of_upid(layers::base_upid(l)) == l);
  }
  CHECK(layers::from_name("INTF") == std::optional<int>(layers::kIntf));
  CHECK(layers::from_name("appl") == std::optional<int>(layers::kAppl));
  CHECK_FALSE(layers::from_name("interface"));
  CHECK_FALSE(layers::from_name("Other"));
  CHECK_FALSE(layers::from_name(""));
}

}  // namespace common_test_layers
