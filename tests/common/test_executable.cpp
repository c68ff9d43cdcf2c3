#include <catch2/catch.hpp>

#include "common/executable.hpp"

// This file's own namespace: the test binary is a unity build (tests/CMakeLists.txt).
namespace common_test_executable {

TEST_CASE("running_executable: the test binary itself", "[common][executable]") {
  auto exe = lmcfg::running_executable();
  REQUIRE(exe.ok());
  CHECK(exe->stem() == "lmcfg_tests");
  CHECK(std::filesystem::exists(*exe));
}

}  // namespace common_test_executable
