#pragma once
// The names of the fleet inventory (docs/fleet.md "The inventory"): a drive's name
// is its file's path in the archive ("press3/z" -> press3/z.json), so it must
// be a path that stays inside the archive's work tree on every file system a
// clone may land on; a line's name is shown on pages and in commit messages.
#include <cstddef>
#include <string_view>

#include "common/result.hpp"

namespace lmcfg::fleet {

// A file or folder name of the archive's work tree: at most 255 bytes
// (NAME_MAX of Linux file systems).
inline constexpr std::size_t kMaxSegmentBytes = 255;

// Whether `name` can be a position name: segments of [A-Za-z0-9._-] separated
// by '/', none empty, "." or "..", none ".git" in any case, none ending in a
// dot (Windows drops it: ".git." is ".git" there), none over
// kMaxSegmentBytes (the last with its ".json"). The message says what is wrong.
// (`fleet check` also refuses names that differ only in case.)
Result<void> check_position_name(std::string_view name);
// Whether `name` can be a line name: one line of UTF-8 without control
// characters (common/text.hpp), at most kMaxSegmentBytes bytes, no backslash,
// its '/'-separated segments none empty, ".", ".." or ".git", none ending in
// a dot or a space (Windows drops them).
Result<void> check_line_name(std::string_view name);

}  // namespace lmcfg::fleet
