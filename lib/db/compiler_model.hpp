#pragma once
// Internal to the UPID database compiler (lib/db/compiler*.cpp): the rows read
// from the sources, the row validators and the SQLite writer.
#include <string>
#include <vector>

#include "db/database.hpp"
#include "db/tsv.hpp"

namespace lmcfg::db::compiler {

// Every row of the sources, validated (upid-db/FORMAT.md).
struct Model {
  std::vector<Profile> profiles;
  std::vector<Parameter> params;
  std::vector<ErrorEntry> errors;
  std::vector<MotionCommand> commands;
  std::vector<DevicenetParameter> dn_params;
  std::vector<DevicenetCommand> dn_commands;
};

// Validates the rows of one known source file (by t.name()) and adds the good
// ones to `m`; every problem goes to the table's diagnostics. Files are read
// in tsv::source_files() order: later ones refer to rows of earlier ones
// (profiles, motion commands).
void load_table(const tsv::Table& t, Model& m);

// Writes the model into a new SQLite file at `path` (schema: lib/db/schema.hpp).
// Returns an empty string, or what failed.
std::string write_db(const Model& m, const std::string& path, const std::string& hash,
                     const std::string& built_from);

}  // namespace lmcfg::db::compiler
