// upiddb-compile SOURCE_DIR OUT_FILE
// Compiles upid-db/*.tsv into the SQLite UPID database at build time. Prints
// "file:line:column: error: ..." for every malformed row and exits 1 without
// touching OUT_FILE; the file is replaced atomically on success.
#include <cstdio>
#include <string>

#include "db/compiler.hpp"

int main(int argc, char** argv) {
  if (argc != 3) {
    std::fprintf(stderr, "usage: upiddb-compile SOURCE_DIR OUT_FILE\n");
    return 2;
  }
  auto rep = lmcfg::db::compile_upid_db(argv[1], argv[2]);
  std::size_t errors = 0;
  for (const auto& d : rep.diagnostics) {
    std::fprintf(stderr, "%s\n", d.str().c_str());
    if (!d.warning) ++errors;
  }
  if (errors != 0 || !rep.written) {
    std::fprintf(stderr, "upiddb-compile: %zu error(s); %s not written\n", errors, argv[2]);
    return 1;
  }
  std::printf("upiddb-compile: wrote %s (%s;", argv[2], rep.content_hash.c_str());
  for (const auto& [table, n] : rep.counts) std::printf(" %s %zu", table.c_str(), n);
  std::printf(")\n");
  return 0;
}
