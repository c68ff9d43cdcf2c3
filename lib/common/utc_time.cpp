#include "common/utc_time.hpp"

namespace lmcfg {

std::tm utc_tm(std::time_t t) {
  std::tm tm{};
  gmtime_r(&t, &tm);
  return tm;
}

std::time_t utc_time_t(std::tm tm) { return timegm(&tm); }

}  // namespace lmcfg
