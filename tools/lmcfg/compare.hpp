#pragma once
// The sides of `lmcfg diff` and `lmcfg report`: each a file ('-': standard
// input), 'defaults' or 'drive' (read live through the link options), loaded
// and compared the same way for both commands, so a report highlights exactly
// what diff lists.
#include <optional>
#include <string>

#include "config/model.hpp"
#include "link_options.hpp"
#include "ops/diff.hpp"

namespace lmcfg::cli {

struct CompareOptions {
  CommonOptions common;
  std::string a, b;  // b empty: one side only (report A)
  bool ignore_metadata = false;
  bool ignore_unit = false;
  bool full = false;
  bool live = false;  // DeviceNet: compare the informational `live` values too
};

struct Compared {
  config::DriveConfig a;
  std::optional<config::DriveConfig> b;
  std::optional<ops::DiffResult> result;  // when b is given
  std::string a_name, b_name;             // "-" shown as "(stdin)"
};

// Loads the sides and, with two, compares them with ops::diff (defaults the
// database and the files do not know are asked from a connected drive). On
// failure prints "lmcfg COMMAND: ..." and returns the exit code; else kOk.
int load_and_compare(const char* command, const CompareOptions& o, const db::Database& db,
                     Compared& out);

// A, B, the link options, --quiet/--db (and --json when `json`),
// --ignore-metadata, --ignore-unit, --full and --live, with the help texts
// both commands share.
void add_compare_options(CLI::App* sub, CompareOptions& o, bool b_required, bool json);

}  // namespace lmcfg::cli
