#include "fleet/names.hpp"

#include <string>

#include "common/bytes.hpp"
#include "common/text.hpp"

namespace lmcfg::fleet {

namespace {

// Windows drops a trailing dot or space from a file or folder name: there
// ".git." is ".git" and "press3 " is "press3" (Microsoft, "Naming Files,
// Paths, and Namespaces"), so such a segment would be another file, or git's
// own folder, in a clone on Windows. The message for `quoted`'s segment
// `seg`, "" when it does not end so.
std::string trailing_dot_or_space(const std::string& quoted, std::string_view seg,
                                  const char* rename) {
  if (seg.empty() || (seg.back() != '.' && seg.back() != ' ')) return {};
  std::string_view stripped = seg;
  while (!stripped.empty() && (stripped.back() == '.' || stripped.back() == ' '))
    stripped.remove_suffix(1);
  return quoted + " has the segment '" + std::string(seg) + "', which ends in " +
         (seg.back() == '.' ? "a dot" : "a space") +
         ": Windows drops a trailing dot or space from a file or folder name (there it is '" +
         std::string(stripped) + "'); " + rename;
}

}  // namespace

Result<void> check_line_name(std::string_view name) {
  if (name.empty()) return Error(Errc::invalid_argument, "line name is empty");
  LMCFG_TRY(check_line("line name", name, kMaxSegmentBytes));
  const std::string quoted = "line name '" + std::string(name) + "'";
  if (name.find('\\') != std::string_view::npos)
    return Error(Errc::invalid_argument, quoted + " contains '\\': use '/' or another character");
  // Line names are not paths today; the same segment rules keep them usable as one.
  std::size_t start = 0;
  for (;;) {
    const auto slash = name.find('/', start);
    const auto seg =
        name.substr(start, slash == std::string_view::npos ? name.npos : slash - start);
    if (seg.empty() || seg == "." || seg == ".." || iequals(seg, ".git")) {
      return Error(Errc::invalid_argument, quoted +
                                               " must be segments separated by '/', none empty, "
                                               "'.', '..' or '.git'");
    }
    if (auto why = trailing_dot_or_space(quoted, seg, "rename the line"); !why.empty())
      return Error(Errc::invalid_argument, why);
    if (slash == std::string_view::npos) return {};
    start = slash + 1;
  }
}

Result<void> check_position_name(std::string_view name) {
  const std::string quoted = "drive name '" + std::string(name) + "'";
  if (name.empty()) return Error(Errc::invalid_argument, "drive name is empty");
  std::size_t start = 0;
  while (start <= name.size()) {
    const auto slash = name.find('/', start);
    const auto seg =
        name.substr(start, slash == std::string_view::npos ? name.npos : slash - start);
    if (seg.empty() || seg == "." || seg == "..") {
      return Error(Errc::invalid_argument,
                   quoted + " must be path segments separated by '/', none empty, '.' or '..'");
    }
    // The name is a path in the archive's work tree: ".git" (any case: on a
    // case-insensitive file system ".GIT" is the same folder) is git's own.
    if (iequals(seg, ".git")) {
      return Error(Errc::invalid_argument,
                   quoted + " has a '" + std::string(seg) +
                       "' segment: that is git's own folder in the archive; rename the drive");
    }
    if (auto why = trailing_dot_or_space(quoted, seg, "rename the drive"); !why.empty())
      return Error(Errc::invalid_argument, why);
    // NAME_MAX of Linux file systems (ext4, xfs): 255 bytes a file or folder name.
    if (seg.size() + (slash == std::string_view::npos ? 5 : 0) > kMaxSegmentBytes) {
      return Error(Errc::invalid_argument,
                   quoted + " has a segment of " + std::to_string(seg.size()) +
                       " bytes; a file name in the archive holds at most 255 bytes (" +
                       std::to_string(kMaxSegmentBytes - 5) +
                       " for the last segment, which gains \".json\"): shorten it");
    }
    for (char ch : seg) {
      const bool ok = (ch >= 'a' && ch <= 'z') || (ch >= 'A' && ch <= 'Z') ||
                      (ch >= '0' && ch <= '9') || ch == '.' || ch == '_' || ch == '-';
      if (!ok) {
        return Error(Errc::invalid_argument, quoted + " contains '" + std::string(1, ch) +
                                                 "' (allowed: letters, digits, . _ - and /)");
      }
    }
    if (slash == std::string_view::npos) break;
    start = slash + 1;
  }
  return {};
}

}  // namespace lmcfg::fleet
