#include "config/config_io.hpp"

#include <algorithm>
#include <cctype>
#include <cstdio>

#include "config/atomic_file.hpp"
#include "config/json_io.hpp"
#include "config/xml_io.hpp"

namespace lmcfg::config {

std::string_view to_string(FileFormat f) noexcept { return f == FileFormat::xml ? "xml" : "json"; }

namespace {
std::string lower(std::string_view s) {
  std::string r(s);
  std::transform(r.begin(), r.end(), r.begin(),
                 [](unsigned char c) { return static_cast<char>(std::tolower(c)); });
  return r;
}
}  // namespace

Result<FileFormat> format_from_name(std::string_view name) {
  const auto l = lower(name);
  if (l == "json") return FileFormat::json;
  if (l == "xml") return FileFormat::xml;
  return Error(Errc::invalid_argument,
               "unknown format \"" + std::string(name) + "\"; expected json or xml");
}

Result<FileFormat> format_from_path(const std::filesystem::path& path) {
  const auto ext = lower(path.extension().string());
  if (ext == ".json") return FileFormat::json;
  if (ext == ".xml") return FileFormat::xml;
  return Error(Errc::invalid_argument,
               path.string() +
                   ": cannot tell the format from the extension; expected .json or "
                   ".xml (or give the format explicitly)");
}

std::optional<FileFormat> sniff_format(std::string_view text) noexcept {
  std::size_t i = 0;
  if (text.substr(0, 3) == "\xEF\xBB\xBF") i = 3;
  while (i < text.size() &&
         (text[i] == ' ' || text[i] == '\t' || text[i] == '\n' || text[i] == '\r'))
    ++i;
  if (i >= text.size()) return std::nullopt;
  if (text[i] == '{') return FileFormat::json;
  if (text[i] == '<') return FileFormat::xml;
  return std::nullopt;
}

Result<DriveConfig> read_config_text(std::string_view text, std::string_view name,
                                     FileFormat format) {
  return format == FileFormat::xml ? read_xml(text, name) : read_json(text, name);
}

namespace {
Result<void> sniffable(std::string_view head, const std::string& name) {
  if (sniff_format(head)) return {};
  std::size_t i = head.substr(0, 3) == "\xEF\xBB\xBF" ? 3 : 0;
  while (i < head.size() &&
         (head[i] == ' ' || head[i] == '\t' || head[i] == '\n' || head[i] == '\r'))
    ++i;
  std::string found = "it is empty";
  if (i < head.size()) {
    char buf[48];
    std::snprintf(buf, sizeof buf, "it starts with byte %02Xh",
                  static_cast<unsigned>(static_cast<unsigned char>(head[i])));
    found = buf;
  }
  return Error(Errc::parse_error, name + ": neither JSON nor XML (" + found +
                                      "); expected a configuration file (.json or .xml)");
}
}  // namespace

Result<DriveConfig> read_config_file(const std::filesystem::path& path,
                                     std::optional<FileFormat> format) {
  if (!format && path != "-") {
    if (auto f = format_from_path(path); f.ok()) format = *f;
  }
  // Without a format from the caller or the extension (stdin, devices, other
  // names) the content decides, and is checked as soon as it starts.
  LMCFG_ASSIGN_OR_RETURN(auto text,
                         read_text_file(path, kMaxInputBytes, format ? nullptr : &sniffable));
  if (!format) format = sniff_format(text);
  return read_config_text(text, input_name(path), *format);
}

Result<std::string> write_config_text(const DriveConfig& cfg, FileFormat format,
                                      const WriteOptions& opts) {
  return format == FileFormat::xml ? write_xml(cfg, opts) : write_json(cfg, opts);
}

Result<void> write_config_file(const DriveConfig& cfg, const std::filesystem::path& path,
                               std::optional<FileFormat> format, const WriteOptions& opts) {
  if (!format) {
    LMCFG_ASSIGN_OR_RETURN(format, format_from_path(path));
  }
  LMCFG_ASSIGN_OR_RETURN(auto text, write_config_text(cfg, *format, opts));
  return write_file_atomic(path, text);
}

}  // namespace lmcfg::config
