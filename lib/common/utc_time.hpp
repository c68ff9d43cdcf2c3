#pragma once
// Calendar time in UTC from seconds since the epoch and back, thread-safe:
// gmtime_r and timegm on POSIX (utc_time.cpp), gmtime_s and _mkgmtime on
// Windows (utc_time_win32.cpp).
#include <ctime>

namespace lmcfg {

std::tm utc_tm(std::time_t t);
// `tm` read as UTC (its tm_wday, tm_yday and tm_isdst are ignored).
std::time_t utc_time_t(std::tm tm);

}  // namespace lmcfg
