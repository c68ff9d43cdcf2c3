// Atomic file replacement (lib/config/atomic_file.cpp).
#include <catch2/catch.hpp>

#include "config/atomic_file.hpp"
#include "config/config_io.hpp"
#include "files.hpp"
#include "test_config_support.hpp"

// This file's own namespace: the test binary is a unity build (tests/CMakeLists.txt).
namespace config_test_atomic_file {

using namespace lmcfg;
using namespace lmcfg::config;
using namespace lmcfg::config::testing;
namespace fs = std::filesystem;

namespace {
struct TempDir : test::ScratchDir {
  TempDir() : test::ScratchDir("cfg-test") {}
  std::size_t entries() const {
    std::size_t n = 0;
    for ([[maybe_unused]] const auto& e : fs::directory_iterator(path)) ++n;
    return n;
  }
};

}  // namespace

TEST_CASE("config: atomic write creates and replaces files", "[config]") {
  TempDir d;
  const auto f = d.path / "out.json";
  REQUIRE(write_file_atomic(f, "one").ok());
  CHECK(slurp(f) == "one");
  REQUIRE(write_file_atomic(f, "two, longer").ok());
  CHECK(slurp(f) == "two, longer");
  CHECK(d.entries() == 1);  // no temporary left behind
}

TEST_CASE("config: atomic write failures leave existing files untouched", "[config]") {
  TempDir d;
  auto r = write_file_atomic(d.path, "x");
  REQUIRE_FALSE(r.ok());
  CHECK(r.error().code == make_error_code(Errc::file_error));
  CHECK(r.error().message == d.path.string() + ": is a directory; expected a file path");

  const auto f = d.path / "keep.json";
  spit(f, "original");
  auto bad = write_file_atomic(f / "child.json", "x");  // parent is a file
  REQUIRE_FALSE(bad.ok());
  CHECK(bad.error().message.find("cannot create a temporary file") != std::string::npos);
  auto missing = write_file_atomic(d.path / "no" / "such" / "dir.json", "x");
  REQUIRE_FALSE(missing.ok());

  // An invalid model is refused before anything is written.
  auto cfg = golden_sinrise();
  cfg.ct_entries.push_back(CtEntry{2, hex("00")});
  REQUIRE_FALSE(write_config_file(cfg, f).ok());
  CHECK(slurp(f) == "original");
  CHECK(d.entries() == 1);
}

TEST_CASE("atomic file: an empty path is refused, nothing written", "[config][atomic_file]") {
  auto empty = write_file_atomic("", "x");
  REQUIRE_FALSE(empty.ok());
  CHECK(empty.error().code == make_error_code(Errc::file_error));
  CHECK(empty.error().message == "empty output path; expected a file path");
}

}  // namespace config_test_atomic_file
