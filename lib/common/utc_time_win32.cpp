#include "common/utc_time.hpp"

namespace lmcfg {

// The C runtime's gmtime_s takes its arguments in the other order than C11's.
std::tm utc_tm(std::time_t t) {
  std::tm tm{};
  gmtime_s(&tm, &t);
  return tm;
}

std::time_t utc_time_t(std::tm tm) { return _mkgmtime(&tm); }

}  // namespace lmcfg
