#pragma once
// Shared helpers of the tests/db/ test files.
#include <unistd.h>

#include <filesystem>
#include <fstream>
#include <string>

#include "common/bytes.hpp"
#include "db/compiler.hpp"
#include "db/database.hpp"

namespace lmcfg::db::test {

inline std::filesystem::path scratch_dir(const std::string& name) {
  auto d = std::filesystem::temp_directory_path() / ("lmcfg-dbtest-" + std::to_string(::getpid())) /
           name;
  std::filesystem::remove_all(d);
  std::filesystem::create_directories(d);
  return d;
}

inline void write_file(const std::filesystem::path& p, const std::string& text) {
  std::ofstream(p, std::ios::binary) << text;
}

// The fixture catalogue (tests/fixtures/upid-db) compiled once per test run.
inline const Database& fixture_db() {
  static const Database db = [] {
    auto dir = scratch_dir("fixture");
    auto out = (dir / "fixture.sqlite").string();
    auto rep = compile_upid_db(LMCFG_SOURCE_DIR "/tests/fixtures/upid-db", out);
    if (!rep.ok())
      throw std::runtime_error("fixture catalogue does not compile: " +
                               rep.diagnostics.front().str());
    auto r = Database::open(out);
    if (!r) throw std::runtime_error(r.error().message);
    return std::move(r).value();
  }();
  return db;
}

// LinRS §12.1, command table entry 2 (64 bytes).
inline Bytes seed_ct_entry() {
  Bytes b = *from_hex("01 A7 FF FF 00 01 40 42 0F 00 20 A1 07 00 40 0D 03 00 40 0D 03 00");
  b.insert(b.end(), 16, 0x00);
  Bytes name = *from_hex("55 6E 6E 61 6D 65 64 00");
  b.insert(b.end(), name.begin(), name.end());
  b.insert(b.end(), 8, 0x00);
  b.insert(b.end(), 10, 0xFF);
  return b;
}

}  // namespace lmcfg::db::test
