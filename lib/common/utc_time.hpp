#pragma once
// Calendar time in UTC from seconds since the epoch, thread-safe:
// gmtime_r on POSIX (utc_time.cpp), gmtime_s on Windows (utc_time_win32.cpp).
#include <ctime>

namespace lmcfg {

std::tm utc_tm(std::time_t t);

}  // namespace lmcfg
