#include <catch2/catch.hpp>
#include <string>

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

TEST_CASE("utc_time_t: reads a calendar time as UTC, whatever the local zone",
          "[common][utc_time]") {
  std::tm tm{};
  tm.tm_year = 101;
  tm.tm_mon = 8;
  tm.tm_mday = 9;
  tm.tm_hour = 1;
  tm.tm_min = 46;
  tm.tm_sec = 40;
  tm.tm_isdst = 1;  // ignored
  CHECK(lmcfg::utc_time_t(tm) == 1000000000);
  CHECK(lmcfg::utc_time_t(lmcfg::utc_tm(0)) == 0);
  CHECK(lmcfg::utc_time_t(lmcfg::utc_tm(1798761599)) == 1798761599);  // 2026-12-31T23:59:59Z
}

TEST_CASE("parse_iso_utc: ISO 8601 UTC times read back, anything else refused",
          "[common][utc_time]") {
  using lmcfg::parse_iso_utc;
  CHECK(parse_iso_utc("1970-01-01T00:00:00Z") == 0);
  CHECK(parse_iso_utc("2001-09-09T01:46:40Z") == 1000000000);
  CHECK(parse_iso_utc("2026-11-24T20:30:00Z") == 1795552200);
  const std::tm leap =
      lmcfg::utc_tm(static_cast<std::time_t>(*parse_iso_utc("2024-02-29T23:59:59Z")));
  CHECK(leap.tm_mon == 1);
  CHECK(leap.tm_mday == 29);
  CHECK(leap.tm_sec == 59);
  for (const std::string bad :
       {"2026-11-24T20:30:00", "2026-11-24T20:30:00+01", "2026-13-24T20:30:00Z",
        "2026-11-24T20:30:00Zjunk", "2026-11-24 20:30:00Z", ""}) {
    INFO(bad);
    CHECK_FALSE(parse_iso_utc(bad).has_value());
  }
}

}  // namespace common_test_utc_time
