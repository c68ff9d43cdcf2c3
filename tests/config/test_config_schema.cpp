// Validates what the writers produce, and the bad fixtures, with the real
// validators behind scripts/validate-json.sh (ajv) and scripts/validate-xml.sh
// (xmllint --schema).
#include <unistd.h>

#include <catch2/catch.hpp>

#include "config/config_io.hpp"
#include "test_config_support.hpp"

// This file's own namespace: the test binary is a unity build (tests/CMakeLists.txt).
namespace config_test_config_schema {

using namespace lmcfg;
using namespace lmcfg::config;
using namespace lmcfg::config::testing;
namespace fs = std::filesystem;

namespace {
std::string script(const char* name) {
  return "'" + (fs::path(LMCFG_SOURCE_DIR) / "scripts" / name).string() + "'";
}
int validate_file(const fs::path& p) {
  const char* s = p.extension() == ".xml" ? "validate-xml.sh" : "validate-json.sh";
  return run(script(s) + " '" + p.string() + "'");
}
bool validators_ready() {
  static const int ok = [] {
    // Installs ajv into tools/node on first use (npm ci from the lock file).
    int rc = run(script("install-node-deps.sh"));
    int xl = run("command -v xmllint");
    return rc == 0 && xl == 0 ? 1 : 0;
  }();
  return ok == 1;
}
}  // namespace

TEST_CASE("config: writer output passes the JSON Schema and XSD", "[config][schema]") {
  if (!validators_ready()) {
    FAIL("validators unavailable: run scripts/install-node-deps.sh and install libxml2-utils");
  }
  const fs::path dir = fs::temp_directory_path() / ("lmcfg-schema-" + std::to_string(::getpid()));
  fs::create_directories(dir);
  std::vector<fs::path> written;
  int k = 0;
  for (const auto& ent : fs::directory_iterator(fixture_dir())) {
    const auto ext = ent.path().extension();
    if (ext != ".json" && ext != ".xml") continue;
    auto cfg = read_config_file(ent.path());
    REQUIRE(cfg.ok());
    for (auto fmt : {FileFormat::json, FileFormat::xml}) {
      const fs::path out = dir / (std::to_string(k++) + "." + std::string(to_string(fmt)));
      REQUIRE(write_config_file(*cfg, out, fmt).ok());
      written.push_back(out);
    }
  }
  DriveConfig empty;
  REQUIRE(write_config_file(empty, dir / "empty.json").ok());
  REQUIRE(write_config_file(empty, dir / "empty.xml").ok());
  written.push_back(dir / "empty.json");
  written.push_back(dir / "empty.xml");
  // A drive without curve and command table groups (scope.drive_lacks).
  DriveConfig lacks;
  lacks.scope.curves = false;
  lacks.scope.command_table = false;
  lacks.scope.drive_lacks = {"curves", "command_table"};
  for (const char* name : {"lacks.json", "lacks.xml"}) {
    REQUIRE(write_config_file(lacks, dir / name).ok());
    written.push_back(dir / name);
  }
  // One validator run per format over every file (node starts once).
  std::string json_files, xml_files;
  for (const auto& p : written)
    (p.extension() == ".xml" ? xml_files : json_files) += " '" + p.string() + "'";
  CHECK(run(script("validate-json.sh") + json_files) == 0);
  CHECK(run(script("validate-xml.sh") + xml_files) == 0);
  for (const auto& p : written) {
    // Spot-check that a single invalid file is noticed among valid ones.
    if (p.extension() != ".json") continue;
    const auto bad = fixture_dir() / "bad" / "json-ct-id-256.json";
    CHECK(run(script("validate-json.sh") + " '" + p.string() + "' '" + bad.string() + "'") == 1);
    break;
  }
  std::error_code ec;
  fs::remove_all(dir, ec);
}

TEST_CASE("config: the validators reject the bad fixtures that are a schema matter",
          "[config][schema]") {
  if (!validators_ready()) {
    FAIL("validators unavailable: run scripts/install-node-deps.sh and install libxml2-utils");
  }
  for (const auto& bc : kBadCases) {
    INFO(bc.file);
    const int rc = validate_file(fixture_dir() / "bad" / bc.file);
    if (bc.schema_rejects) {
      CHECK(rc == 1);
    } else {
      CHECK(rc == 0);  // valid by schema: only lmcfg's semantic checks catch it
    }
  }
}

}  // namespace config_test_config_schema
