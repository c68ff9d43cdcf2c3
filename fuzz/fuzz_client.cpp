// libFuzzer target; the entry point lives in fuzz_entries.hpp (shared with
// tests/config/test_reliability_regressions.cpp).
#include "fuzz_entries.hpp"

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  lmcfg::fuzz::client_entry(data, size);
  return 0;
}
