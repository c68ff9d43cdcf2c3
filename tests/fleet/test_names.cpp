// The inventory's names (lib/fleet/names.cpp, docs/fleet.md "The inventory"): a
// drive's name is its file's path in the archive, a line's name one line of
// text; each refusal with its exact message.
#include <catch2/catch.hpp>

#include "fleet/names.hpp"

// This file's own namespace: the test binary is a unity build (tests/CMakeLists.txt).
namespace fleet_test_names {

using namespace lmcfg;

namespace {

std::string position_problem(const std::string& name) {
  auto r = fleet::check_position_name(name);
  REQUIRE_FALSE(r.ok());
  CHECK(r.error().code == Errc::invalid_argument);
  return r.error().message;
}
std::string line_problem(const std::string& name) {
  auto r = fleet::check_line_name(name);
  REQUIRE_FALSE(r.ok());
  CHECK(r.error().code == Errc::invalid_argument);
  return r.error().message;
}

}  // namespace

TEST_CASE("fleet names: drive names are archive paths that stay in the work tree",
          "[fleet][names]") {
  CHECK(fleet::check_position_name("press3/z-axis").ok());
  CHECK(fleet::check_position_name("a.b/c_d").ok());
  CHECK(fleet::check_position_name(".gitkeep").ok());  // only ".git" itself is git's
  CHECK(position_problem(".git/config") ==
        "drive name '.git/config' has a '.git' segment: that is git's own folder in the archive; "
        "rename the drive");
  CHECK(position_problem("press3/.GiT") ==
        "drive name 'press3/.GiT' has a '.GiT' segment: that is git's own folder in the "
        "archive; rename the drive");
  CHECK(position_problem("a//b") ==
        "drive name 'a//b' must be path segments separated by '/', none empty, '.' or '..'");
  CHECK(position_problem("../b") ==
        "drive name '../b' must be path segments separated by '/', none empty, '.' or '..'");
  CHECK(position_problem("a\\b") ==
        "drive name 'a\\b' contains '\\' (allowed: letters, digits, . _ - and /)");
  CHECK(position_problem("a\nb") ==
        "drive name 'a\nb' contains '\n' (allowed: letters, digits, . _ - and /)");
  CHECK(position_problem("") == "drive name is empty");
}

TEST_CASE("fleet names: a segment holds at most 255 bytes, the last 250 (it gains .json)",
          "[fleet][names]") {
  CHECK(fleet::check_position_name(std::string(255, 'a') + "/" + std::string(250, 'b')).ok());
  const std::string last(251, 'b');
  CHECK(position_problem(last) ==
        "drive name '" + last +
            "' has a segment of 251 bytes; a file name in the archive holds at most 255 bytes "
            "(250 for the last segment, which gains \".json\"): shorten it");
  const std::string folder(256, 'a');
  CHECK(position_problem(folder + "/z") ==
        "drive name '" + folder +
            "/z' has a segment of 256 bytes; a file name in the archive holds at most 255 "
            "bytes (250 for the last segment, which gains \".json\"): shorten it");
}

TEST_CASE("fleet names: line names are one line of UTF-8 text", "[fleet][names]") {
  CHECK(fleet::check_line_name("line 1").ok());
  CHECK(fleet::check_line_name("Halle 2/Presse \xC3\xBC").ok());
  CHECK(line_problem("") == "line name is empty");
  CHECK(line_problem("l1\nOperator: x") ==
        "line name contains a control character (0x0A at offset 2): give one line without "
        "control characters");
  CHECK(line_problem("l\xFF") ==
        "line name is not valid UTF-8 (byte 0xFF at offset 1): send UTF-8 text");
  CHECK(line_problem("a\\b") == "line name 'a\\b' contains '\\': use '/' or another character");
  CHECK(line_problem("a/.Git") ==
        "line name 'a/.Git' must be segments separated by '/', none empty, '.', '..' or '.git'");
  CHECK(line_problem("..") ==
        "line name '..' must be segments separated by '/', none empty, '.', '..' or '.git'");
  CHECK(line_problem(std::string(256, 'l')) ==
        "line name is 256 bytes long, at most 255 are accepted: shorten it");
}

TEST_CASE("fleet names: no segment ends in a dot or a space (Windows drops them)",
          "[fleet][names]") {
  CHECK(position_problem(".git.") ==
        "drive name '.git.' has the segment '.git.', which ends in a dot: Windows drops a "
        "trailing dot or space from a file or folder name (there it is '.git'); rename the drive");
  CHECK(position_problem("p/.git.") ==
        "drive name 'p/.git.' has the segment '.git.', which ends in a dot: Windows drops a "
        "trailing dot or space from a file or folder name (there it is '.git'); rename the drive");
  CHECK(position_problem("press3./z") ==
        "drive name 'press3./z' has the segment 'press3.', which ends in a dot: Windows drops a "
        "trailing dot or space from a file or folder name (there it is 'press3'); rename the "
        "drive");
  CHECK(position_problem("press3 /z") ==
        "drive name 'press3 /z' has the segment 'press3 ', which ends in a space: Windows drops "
        "a trailing dot or space from a file or folder name (there it is 'press3'); rename the "
        "drive");
  CHECK(position_problem("press3/z.") ==
        "drive name 'press3/z.' has the segment 'z.', which ends in a dot: Windows drops a "
        "trailing dot or space from a file or folder name (there it is 'z'); rename the drive");
  CHECK(fleet::check_position_name("press3/.z").ok());  // a leading dot is kept
  CHECK(fleet::check_position_name("a.b.c/d").ok());
  CHECK(line_problem("press3 /z") ==
        "line name 'press3 /z' has the segment 'press3 ', which ends in a space: Windows drops "
        "a trailing dot or space from a file or folder name (there it is 'press3'); rename the "
        "line");
  CHECK(line_problem("hall 2/.git.") ==
        "line name 'hall 2/.git.' has the segment '.git.', which ends in a dot: Windows drops a "
        "trailing dot or space from a file or folder name (there it is '.git'); rename the line");
  CHECK(line_problem("line 1 ") ==
        "line name 'line 1 ' has the segment 'line 1 ', which ends in a space: Windows drops a "
        "trailing dot or space from a file or folder name (there it is 'line 1'); rename the "
        "line");
  CHECK(fleet::check_line_name("hall 2/line 1").ok());
}

}  // namespace fleet_test_names
