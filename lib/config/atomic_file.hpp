#pragma once
// Safe file replacement: write a temporary file in the target's directory,
// fsync it, rename it over the target, fsync the directory. On any failure the
// temporary file is removed and an existing target is left untouched.
#include <filesystem>
#include <string>
#include <string_view>

#include "common/result.hpp"

namespace lmcfg::config {

// Errors (Errc::file_error) name the path and the failing step, e.g.
// "out.json: is a directory; expected a file path".
Result<void> write_file_atomic(const std::filesystem::path& path, std::string_view content);

// Whole file as text; Errc::file_error / not_found with the path in the message.
Result<std::string> read_text_file(const std::filesystem::path& path);

}  // namespace lmcfg::config
