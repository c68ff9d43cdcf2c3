#pragma once
// `promtool check metrics` (Debian package prometheus) over a /metrics text:
// the real linter of the exposition format. Skipped with a printed reason when
// promtool is absent, unless LMCFG_REQUIRE_PROMTOOL=1.
#include <catch2/catch.hpp>
#include <cstdlib>
#include <filesystem>
#include <string>

#include "files.hpp"

namespace lmcfg::test {

inline void check_with_promtool(const std::string& text, const std::filesystem::path& dir) {
  const bool have = std::system("command -v promtool >/dev/null 2>&1") == 0;
  const char* require = std::getenv("LMCFG_REQUIRE_PROMTOOL");
  if (!have && !(require && std::string(require) == "1")) {
    WARN(
        "SKIP: promtool not found (Debian package prometheus); set LMCFG_REQUIRE_PROMTOOL=1 to "
        "fail instead");
    return;
  }
  REQUIRE(have);
  spit(dir / "metrics.txt", text);
  const std::string cmd = "promtool check metrics < '" + (dir / "metrics.txt").string() + "' > '" +
                          (dir / "promtool.txt").string() + "' 2>&1";
  const int rc = std::system(cmd.c_str());
  INFO(slurp(dir / "promtool.txt"));
  CHECK(rc == 0);
  CHECK(slurp(dir / "promtool.txt").empty());
}

}  // namespace lmcfg::test
