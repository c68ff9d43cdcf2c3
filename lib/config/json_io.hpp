#pragma once
// JSON form of the drive configuration (docs/config-files.md,
// schemas/lmcfg-config-v3.schema.json). See config_io.hpp for the
// format-independent entry points.
#include <filesystem>
#include <string>
#include <string_view>

#include "config/config_io.hpp"

namespace lmcfg::config {

Result<DriveConfig> read_json(std::string_view text, std::string_view name);
Result<DriveConfig> read_json_file(const std::filesystem::path& path);
Result<std::string> write_json(const DriveConfig& cfg, const WriteOptions& opts = {});
Result<void> write_json_file(const DriveConfig& cfg, const std::filesystem::path& path,
                             const WriteOptions& opts = {});

// 1-based line and column of a byte offset (0-based) in text.
struct TextPos {
  std::size_t line = 1;
  std::size_t column = 1;
};
TextPos text_position(std::string_view text, std::size_t offset) noexcept;

}  // namespace lmcfg::config
