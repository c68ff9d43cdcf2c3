// Atomic file replacement and bounded file reading (lib/config/atomic_file.cpp).
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

Result<void> refuse_zero(std::string_view head, const std::string& name) {
  if (head.find('\0') != std::string_view::npos)
    return Error(Errc::parse_error, name + ": holds a NUL byte");
  return {};
}
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

TEST_CASE("atomic file: read_text_file reads whole files and names what it refuses",
          "[config][atomic_file]") {
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

TEST_CASE("atomic file: a stream is read up to the limit, its head checked once it has text",
          "[config][atomic_file]") {
  // /dev/zero never ends: the head check refuses it after the first block.
  auto zero = read_text_file("/dev/zero", kMaxInputBytes, refuse_zero);
  REQUIRE_FALSE(zero.ok());
  CHECK(zero.error().code == make_error_code(Errc::parse_error));
  CHECK(zero.error().message == "/dev/zero: holds a NUL byte");
  // Without a head check the limit ends it.
  auto endless = read_text_file("/dev/zero", 100000);
  REQUIRE_FALSE(endless.ok());
  CHECK(endless.error().message ==
        "/dev/zero: more than 100000 bytes (an endless stream?); a configuration is far smaller");
  // A blank file is checked at its end.
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

}  // namespace config_test_atomic_file
