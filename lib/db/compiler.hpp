#pragma once
// The UPID database compiler: reads upid-db/*.tsv (format: upid-db/FORMAT.md),
// validates every row, and writes the SQLite file atomically (temp + rename).
// Used at build time by upid-db/compiler (upiddb-compile) and by the tests.
#include <cstdint>
#include <map>
#include <string>
#include <string_view>
#include <vector>

#include "db/tsv.hpp"

namespace lmcfg::db {

// Diagnostic (file:line:column: error: message): lib/db/tsv.hpp.

struct CompileReport {
  std::vector<Diagnostic> diagnostics;        // errors and warnings, in file order
  std::map<std::string, std::size_t> counts;  // rows per table written
  std::string content_hash;                   // "fnv1a64:<16 hex digits>"
  bool written = false;
  bool ok() const;  // no error diagnostics
};

// Known source files, in processing order.
const std::vector<std::string>& upid_db_source_files();

// Compiles every known *.tsv in `source_dir` into `out_path`. Missing files
// count as empty tables; unknown *.tsv files draw a warning. On any error the
// output is not touched. An empty out_path only validates.
CompileReport compile_upid_db(const std::string& source_dir, const std::string& out_path);

// FNV-1a 64-bit, chainable: fnv1a64(b, fnv1a64(a)) == fnv1a64(a + b).
inline constexpr std::uint64_t kFnv1a64Offset = 0xcbf29ce484222325ull;
std::uint64_t fnv1a64(std::string_view data, std::uint64_t h = kFnv1a64Offset) noexcept;

}  // namespace lmcfg::db
