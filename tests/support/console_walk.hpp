#pragma once
// A walk through the web console in headless Chromium
// (tests/browser/walk-console.js over the DevTools protocol): the steps as
// JSON, their results back; screenshots kept in build/tests/console-shots/.
#include <catch2/catch.hpp>
#include <cstdlib>
#include <filesystem>
#include <nlohmann/json.hpp>
#include <string>

#include "browser.hpp"
#include "files.hpp"

namespace lmcfg::test {

inline std::filesystem::path console_shots_dir() {
  const auto d = std::filesystem::path(LMCFG_BINARY_DIR) / "tests" / "console-shots";
  std::filesystem::create_directories(d);
  return d;
}

// Runs the steps in Chromium; the walk's JSON, or null when skipped.
inline nlohmann::json console_walk(const std::filesystem::path& work, const nlohmann::json& steps) {
  const std::string chromium = find_chromium();
  if (chromium.empty()) {
    if (browser_required()) FAIL("chromium not found, and LMCFG_REQUIRE_BROWSER=1");
    WARN("SKIP: console browser walk: chromium not found (apt-get install chromium)");
    return nullptr;
  }
  spit(work / "steps.json", steps.dump(1));
  const std::string cmd =
      "node '" + std::string(LMCFG_SOURCE_DIR) + "/tests/browser/walk-console.js' --chromium '" +
      chromium + "' --steps '" + (work / "steps.json").string() + "' >'" +
      (work / "walk.json").string() + "' 2>'" + (work / "walk.err").string() + "'";
  const int rc = std::system(cmd.c_str());
  INFO(slurp(work / "walk.err"));
  REQUIRE(rc == 0);
  return nlohmann::json::parse(slurp(work / "walk.json"));
}

inline nlohmann::json console_shot(const std::string& name, bool full_page = true) {
  return {
      {"op", "shot"}, {"file", (console_shots_dir() / name).string()}, {"full_page", full_page}};
}

}  // namespace lmcfg::test
