#pragma once
// Headless Chromium for the browser tests (tests/browser/*.js over the
// DevTools protocol): where it is, and whether its absence fails the test
// (LMCFG_REQUIRE_BROWSER=1, as CI sets it) or skips the browser checks.
#include <unistd.h>

#include <cstdlib>
#include <string>

namespace lmcfg::test {

// $LMCFG_CHROMIUM, else the usual install paths; "" when there is none.
inline std::string find_chromium() {
  if (const char* e = std::getenv("LMCFG_CHROMIUM"); e && *e) return e;
  for (const char* c : {"/usr/bin/chromium", "/usr/bin/chromium-browser", "/usr/bin/google-chrome"})
    if (::access(c, X_OK) == 0) return c;
  return "";
}

inline bool browser_required() {
  const char* e = std::getenv("LMCFG_REQUIRE_BROWSER");
  return e && std::string(e) == "1";
}

}  // namespace lmcfg::test
