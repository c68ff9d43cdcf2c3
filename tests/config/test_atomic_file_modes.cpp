// Atomic file replacement and POSIX files (lib/config/atomic_file.cpp): a new
// file gets the mode open(2) would give it, the umask honoured; a replaced
// file keeps its mode; a device is refused, and read as an endless stream
// (lib/config/text_file.cpp). Apart from test_atomic_file.cpp and
// test_text_file.cpp because Windows has no umask, group modes or /dev
// (tests/CMakeLists.txt).
#include <sys/stat.h>

#include <catch2/catch.hpp>

#include "config/atomic_file.hpp"
#include "files.hpp"

// This file's own namespace: the test binary is a unity build (tests/CMakeLists.txt).
namespace config_test_atomic_file_modes {

using namespace lmcfg;
using namespace lmcfg::config;
namespace fs = std::filesystem;

TEST_CASE("config: atomic write gives a new file the mode open(2) would, the umask honoured",
          "[config]") {
  test::ScratchDir d("cfg-modes");
  const mode_t old = ::umask(027);  // the test binary's own threads create no files meanwhile
  auto r = write_file_atomic(d.path / "private.json", "x");
  ::umask(022);
  auto r2 = write_file_atomic(d.path / "usual.json", "x");
  ::umask(old);
  REQUIRE(r.ok());
  REQUIRE(r2.ok());
  CHECK((fs::status(d.path / "private.json").permissions() & fs::perms::all) ==
        (fs::perms::owner_read | fs::perms::owner_write | fs::perms::group_read));
  CHECK((fs::status(d.path / "usual.json").permissions() & fs::perms::all) ==
        (fs::perms::owner_read | fs::perms::owner_write | fs::perms::group_read |
         fs::perms::others_read));
}

TEST_CASE("config: atomic write keeps the mode of the file it replaces", "[config]") {
  test::ScratchDir d("cfg-modes");
  const auto f = d.path / "axis.json";
  REQUIRE(write_file_atomic(f, "one").ok());
  fs::permissions(f, fs::perms::owner_read | fs::perms::owner_write | fs::perms::group_read);
  REQUIRE(write_file_atomic(f, "three").ok());
  CHECK((fs::status(f).permissions() & fs::perms::all) ==
        (fs::perms::owner_read | fs::perms::owner_write | fs::perms::group_read));
}

TEST_CASE("atomic file: a device is refused, nothing written", "[config][atomic_file]") {
  auto dev = write_file_atomic("/dev/null", "x");
  REQUIRE_FALSE(dev.ok());
  CHECK(dev.error().code == make_error_code(Errc::file_error));
  CHECK(dev.error().message == "/dev/null: is not a regular file; expected a file path");
}

namespace {
Result<void> refuse_zero(std::string_view head, const std::string& name) {
  if (head.find('\0') != std::string_view::npos)
    return Error(Errc::parse_error, name + ": holds a NUL byte");
  return {};
}
}  // namespace

TEST_CASE("text file: a device stream is read up to the limit, its head checked once it has text",
          "[config][text_file]") {
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
}

}  // namespace config_test_atomic_file_modes
