// Bounded reading of input files (lib/config/text_file.cpp): sizes, the head
// check and the messages naming what was refused (an endless device stream:
// test_atomic_file_modes.cpp, POSIX only).
#include <catch2/catch.hpp>

#include "config/atomic_file.hpp"
#include "files.hpp"
#include "test_config_support.hpp"

// This file's own namespace: the test binary is a unity build (tests/CMakeLists.txt).
namespace config_test_text_file {

using namespace lmcfg;
using namespace lmcfg::config;
using namespace lmcfg::config::testing;
namespace fs = std::filesystem;

namespace {
struct TempDir : test::ScratchDir {
  TempDir() : test::ScratchDir("cfg-text") {}
};
}  // namespace

TEST_CASE("text file: read_text_file reads whole files and names what it refuses",
          "[config][text_file]") {
  TempDir d;
  const auto f = d.path / "in.json";
  spit(f, "{\"a\": 1}\n");
  CHECK(read_text_file(f).value() == "{\"a\": 1}\n");
  CHECK(input_name(f) == f.string());
  CHECK(input_name("-") == "(stdin)");

  auto missing = read_text_file(d.path / "none.json");
  REQUIRE_FALSE(missing.ok());
  CHECK(missing.error().code == make_error_code(Errc::not_found));
  CHECK(missing.error().message == (d.path / "none.json").string() + ": no such file");

  auto dir = read_text_file(d.path);
  REQUIRE_FALSE(dir.ok());
  CHECK(dir.error().code == make_error_code(Errc::file_error));
  CHECK(dir.error().message == d.path.string() + ": is a directory; expected a file");

  // A regular file over the limit is refused from its size, before reading.
  spit(f, std::string(2 << 20, ' '));
  auto big = read_text_file(f, std::size_t{1} << 20);
  REQUIRE_FALSE(big.ok());
  CHECK(big.error().message ==
        f.string() + ": 2097152 bytes, larger than any configuration (at most 1 MiB)");
  auto odd = read_text_file(f, 1000);
  REQUIRE_FALSE(odd.ok());
  CHECK(odd.error().message ==
        f.string() + ": 2097152 bytes, larger than any configuration (at most 1000 bytes)");
}

TEST_CASE("text file: a blank file is head-checked at its end", "[config][text_file]") {
  TempDir d;
  const auto blank = d.path / "blank.json";
  spit(blank, "  \n");
  int calls = 0;
  static int* counter = nullptr;
  counter = &calls;
  auto seen = read_text_file(blank, kMaxInputBytes, [](std::string_view head, const std::string&) {
    ++*counter;
    CHECK(head == "  \n");
    return Result<void>{};
  });
  REQUIRE(seen.ok());
  CHECK(calls == 1);
}

}  // namespace config_test_text_file
