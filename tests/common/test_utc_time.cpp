#include <catch2/catch.hpp>

#include "common/utc_time.hpp"

// This file's own namespace: the test binary is a unity build (tests/CMakeLists.txt).
namespace common_test_utc_time {

// Known instants of the Unix epoch (POSIX "Seconds Since the Epoch").
TEST_CASE("utc_tm: the epoch and one billion seconds after it", "[common][utc_time]") {
  const std::tm epoch = lmcfg::utc_tm(0);
  CHECK(epoch.tm_year == 70);
  CHECK(epoch.tm_mon == 0);
  CHECK(epoch.tm_mday == 1);
  CHECK(epoch.tm_hour == 0);
  const std::tm billion = lmcfg::utc_tm(1000000000);  // 2001-09-09T01:46:40Z
  CHECK(billion.tm_year == 101);
  CHECK(billion.tm_mon == 8);
  CHECK(billion.tm_mday == 9);
  CHECK(billion.tm_hour == 1);
  CHECK(billion.tm_min == 46);
  CHECK(billion.tm_sec == 40);
}

}  // namespace common_test_utc_time
