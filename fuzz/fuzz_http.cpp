// libFuzzer target: raw HTTP requests into lmcfg serve's routes and handlers
// (fuzz/fuzz_http_entry.hpp, shared with tests/serve/test_http_fuzz.cpp).
#include "fuzz_http_entry.hpp"

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  lmcfg::fuzz::http_entry(data, size);
  return 0;
}
