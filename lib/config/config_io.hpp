#pragma once
// Reading and writing configuration files in either format.
//
//   auto cfg = lmcfg::config::read_config_file("axis1.json");          // format from extension
//   auto r   = lmcfg::config::write_config_file(*cfg, "axis1.xml");    // atomic replace
//
// Readers return Errc::parse_error (syntax, wrong types), unsupported_version
// (format/format_version), validation_failed (semantic), file_error/not_found.
// Messages: JSON "file:line:column: /json/pointer: what was expected";
//           XML  "file: /lmcfg/parameters/layer[2]/param[3]/@value: what was expected".
#include <filesystem>
#include <optional>
#include <string>
#include <string_view>

#include "common/result.hpp"
#include "config/model.hpp"

namespace lmcfg::config {

enum class FileFormat { json, xml };
std::string_view to_string(FileFormat f) noexcept;  // "json" / "xml"
// "json"/"xml" (case-insensitive); Errc::invalid_argument otherwise.
Result<FileFormat> format_from_name(std::string_view name);
// From the extension ".json"/".xml" (case-insensitive); Errc::invalid_argument otherwise.
Result<FileFormat> format_from_path(const std::filesystem::path& path);
// From the first non-blank character: '{' json, '<' xml; nullopt otherwise.
std::optional<FileFormat> sniff_format(std::string_view text) noexcept;

struct WriteOptions {
  // Writes "decoded" views (curve name, setpoints, ...) next to the raw bytes.
  bool include_decoded = true;
  // Optional: decoded command table entries (summary, named params).
  const CtEntryDecoder* ct_decoder = nullptr;
};

// Text in, model out. `name` is used in messages only. Version 1 files are
// migrated (see config/migrate.hpp). The result is canonicalized.
Result<DriveConfig> read_config_text(std::string_view text, std::string_view name,
                                     FileFormat format);
// Format from `format`, else from the extension, else sniffed from the content
// ("-" = standard input, always sniffed). Inputs over kMaxInputBytes are
// refused (atomic_file.hpp); content that starts with neither '{' nor '<' is
// refused after its first block when the format comes from the content.
Result<DriveConfig> read_config_file(const std::filesystem::path& path,
                                     std::optional<FileFormat> format = std::nullopt);

// Model out as canonical text (validates first: Errc::validation_failed).
Result<std::string> write_config_text(const DriveConfig& cfg, FileFormat format,
                                      const WriteOptions& opts = {});
// Format from `format`, else from the extension. Atomic: see atomic_file.hpp.
Result<void> write_config_file(const DriveConfig& cfg, const std::filesystem::path& path,
                               std::optional<FileFormat> format = std::nullopt,
                               const WriteOptions& opts = {});

}  // namespace lmcfg::config
