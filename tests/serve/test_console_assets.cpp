// The console's embedded stylesheet and script and its two Content-Security-
// Policies (lib/serve/console_assets.cpp): exact policies, nothing loaded
// from elsewhere, a style for every status badge the pages render, and a
// script that node parses.
#include <catch2/catch.hpp>
#include <cstdlib>

#include "files.hpp"
#include "serve/console.hpp"
#include "subprocess.hpp"

// This file's own namespace: the test binary is a unity build (tests/CMakeLists.txt).
namespace serve_test_console_assets {

using namespace lmcfg;

TEST_CASE("console assets: the console's and the report pages' Content-Security-Policy",
          "[serve][console_assets]") {
  CHECK(serve::Console::content_security_policy() ==
        "default-src 'none'; style-src 'self'; script-src 'self'; img-src 'self'; "
        "connect-src 'self'; form-action 'self'; base-uri 'none'; frame-ancestors 'none'");
  // The report pages (lmcfg report's HTML) have their style inline and no script.
  CHECK(serve::Console::report_security_policy() ==
        "default-src 'none'; style-src 'unsafe-inline'; frame-ancestors 'none'");
}

TEST_CASE("console assets: the stylesheet loads nothing and styles every status badge",
          "[serve][console_assets]") {
  const std::string css(serve::Console::stylesheet());
  REQUIRE_FALSE(css.empty());
  // Served by lmcfg itself: no font, no image, no other stylesheet.
  for (const char* outside : {"http:", "https:", "//", "@import", "url(", "@font-face"}) {
    INFO(outside);
    CHECK(css.find(outside) == std::string::npos);
  }
  // pages.cpp's badge(): class "s-" + the status with blanks as '-'
  // ("unknown" keeps .status's own colour).
  for (const char* cls : {".status {", ".s-ok {", ".s-drift {", ".s-failed {", ".s-replaced {",
                          ".s-never-backed-up {"}) {
    INFO(cls);
    CHECK(css.find(cls) != std::string::npos);
  }
  CHECK(css.find("@media print") != std::string::npos);
  long depth = 0;
  for (char c : css) {
    depth += c == '{' ? 1 : c == '}' ? -1 : 0;
    REQUIRE(depth >= 0);
  }
  CHECK(depth == 0);
}

TEST_CASE(
    "console assets: the script is strict, refreshes marked sections from this page, "
    "and node parses it",
    "[serve][console_assets]") {
  const std::string js(serve::Console::script());
  CHECK(js.rfind("'use strict';", 0) == 0);
  CHECK(js.find("document.querySelectorAll('[data-refresh][id]')") != std::string::npos);
  // Only this page's own URL (connect-src 'self'), with the session cookie.
  CHECK(js.find("fetch(location.href, { credentials: 'same-origin', redirect: 'manual' })") !=
        std::string::npos);
  for (const char* unsafe : {"http:", "https:", "eval(", "innerHTML", "document.write"}) {
    INFO(unsafe);
    CHECK(js.find(unsafe) == std::string::npos);
  }
  if (test::shell_output("command -v node").empty()) {
    WARN("SKIP: node --check: node not found");
    return;
  }
  test::ScratchDir d("console-js");
  test::spit(d.path / "console.js", js);
  const std::string cmd = "node --check '" + (d.path / "console.js").string() + "' 2>&1";
  INFO(test::shell_output(cmd));
  CHECK(std::system(cmd.c_str()) == 0);
}

}  // namespace serve_test_console_assets
