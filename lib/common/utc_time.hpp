#pragma once
// Calendar time in UTC from seconds since the epoch and back, thread-safe:
// gmtime_r and timegm on POSIX (utc_time.cpp), gmtime_s and _mkgmtime on
// Windows (utc_time_win32.cpp).
#include <cstdint>
#include <cstdio>
#include <ctime>
#include <optional>
#include <string>

namespace lmcfg {

std::tm utc_tm(std::time_t t);
// `tm` read as UTC (its tm_wday, tm_yday and tm_isdst are ignored).
std::time_t utc_time_t(std::tm tm);

// "2026-11-24T20:30:00Z" (ISO 8601 UTC as lmcfg writes it) as seconds since
// the epoch; nullopt for anything else: no 'Z', text after it, a field out
// of its calendar range. sscanf counts conversions only, so the %n check is
// what refuses a missing 'Z' or trailing text.
inline std::optional<std::int64_t> parse_iso_utc(const std::string& text) {
  std::tm tm{};
  char zone = 0;
  int used = 0;
  if (std::sscanf(text.c_str(), "%4d-%2d-%2dT%2d:%2d:%2d%c%n", &tm.tm_year, &tm.tm_mon, &tm.tm_mday,
                  &tm.tm_hour, &tm.tm_min, &tm.tm_sec, &zone, &used) != 7 ||
      zone != 'Z' || static_cast<std::size_t>(used) != text.size() || tm.tm_mon < 1 ||
      tm.tm_mon > 12 || tm.tm_mday < 1 || tm.tm_mday > 31 || tm.tm_hour > 23 || tm.tm_min > 59 ||
      tm.tm_sec > 60)
    return std::nullopt;
  tm.tm_year -= 1900;
  tm.tm_mon -= 1;
  return static_cast<std::int64_t>(utc_time_t(tm));
}

}  // namespace lmcfg
