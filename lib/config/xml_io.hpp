#pragma once
// XML form of the drive configuration (docs/config-files.md,
// schemas/lmcfg-config-v3.xsd). See config_io.hpp for the format-independent
// entry points.
#include <filesystem>
#include <string>
#include <string_view>

#include "config/config_io.hpp"

namespace lmcfg::config {

Result<DriveConfig> read_xml(std::string_view text, std::string_view name);
Result<DriveConfig> read_xml_file(const std::filesystem::path& path);
Result<std::string> write_xml(const DriveConfig& cfg, const WriteOptions& opts = {});
Result<void> write_xml_file(const DriveConfig& cfg, const std::filesystem::path& path,
                            const WriteOptions& opts = {});

}  // namespace lmcfg::config
