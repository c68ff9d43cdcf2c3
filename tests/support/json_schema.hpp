#pragma once
// A report checked against its JSON Schema (schemas/NAME) with the real
// validator the project installs (ajv, scripts/install-node-deps.sh).
#include <cstdlib>
#include <filesystem>
#include <string>

#include "files.hpp"

namespace lmcfg::test {

// ajv's verdict on `json` against schemas/`schema` (draft 2020-12, strict);
// the document is written to dir/report.json first.
inline bool schema_valid(const std::filesystem::path& dir, const std::string& schema,
                         const std::string& json) {
  namespace fs = std::filesystem;
  spit(dir / "report.json", json);
  const auto ajv = fs::path(LMCFG_SOURCE_DIR) / "tools" / "node" / "node_modules" / ".bin" / "ajv";
  const auto s = fs::path(LMCFG_SOURCE_DIR) / "schemas" / schema;
  const std::string cmd = "'" + ajv.string() + "' validate --spec=draft2020 --strict=true -s '" +
                          s.string() + "' -d '" + (dir / "report.json").string() +
                          "' >/dev/null 2>&1";
  return std::system(cmd.c_str()) == 0;
}

}  // namespace lmcfg::test
