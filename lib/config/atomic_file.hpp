#pragma once
// Safe file replacement: write a temporary file in the target's directory,
// fsync it, rename it over the target, fsync the directory. On any failure the
// temporary file is removed and an existing target is left untouched.
#include <filesystem>
#include <string>
#include <string_view>

#include "common/result.hpp"

namespace lmcfg::config {

// A new file's mode is 0666 less the process's umask, as open(2) would make
// it; a replaced file keeps its mode.
// Errors (Errc::file_error) name the path and the failing step, e.g.
// "out.json: is a directory; expected a file path".
Result<void> write_file_atomic(const std::filesystem::path& path, std::string_view content);

// Appends `line` to `path` (created 0600 if missing) in one write at the end
// of the file, so a concurrent writer's line goes before or after it, never
// into it (O_APPEND on POSIX, FILE_APPEND_DATA on Windows). Errors
// (Errc::file_error) read "<path>: cannot open: <reason>" (or cannot write,
// short write, cannot close).
Result<void> append_file(const std::filesystem::path& path, std::string_view line);

// Inputs larger than any real configuration (a full capture with 100 curves
// is a few MB) are refused: 256 MiB.
inline constexpr std::size_t kMaxInputBytes = std::size_t{256} << 20;

// Whole file as text; Errc::file_error / not_found with the path in the message.
// A regular file larger than `max_bytes` is refused before reading
// (Errc::file_error); a stream (pipe, device) is read until it ends or exceeds
// `max_bytes`. "-" reads standard input, named "(stdin)" in messages.
// `check_head`, when given, sees the text read so far once it holds a
// non-blank character (or at the end, if it never does) and may refuse it, so
// an endless stream that cannot be the expected content is refused after its
// first block (`lmcfg diff defaults /dev/zero`).
using HeadCheck = Result<void> (*)(std::string_view head, const std::string& name);
Result<std::string> read_text_file(const std::filesystem::path& path,
                                   std::size_t max_bytes = kMaxInputBytes,
                                   HeadCheck check_head = nullptr);
// "(stdin)" for "-", else the path.
std::string input_name(const std::filesystem::path& path);

}  // namespace lmcfg::config
