#pragma once
// A file sent from the drive's page (docs/ui.md "Uploads"): the browser's
// multipart/form-data body (RFC 7578) taken apart into its fields, the
// file's name and bytes. This knows no folder and no drive: ui/desk.hpp
// stores the file, ui/server.hpp checks the request first.
#include <cstddef>
#include <map>
#include <string>
#include <string_view>

#include "common/result.hpp"

namespace lmcfg::ui {

// The most bytes an uploaded configuration file may have. A backup with
// 100 curves of 1000 setpoints each is under 2 MiB as JSON.
inline constexpr std::size_t kMaxUpload = 4u << 20;
// The body's room above the file for the form's other fields and the
// multipart framing (the HTTP server's body limit is kMaxUpload + this).
inline constexpr std::size_t kUploadFraming = 64u << 10;

struct UploadForm {
  std::map<std::string, std::string> fields;  // the text fields (csrf, key, then)
  std::string file_field;                     // the file part's field name ("" = none)
  std::string file_name;                      // as the browser gave it
  std::string file;                           // its bytes
};

// Content-Type "multipart/form-data; boundary=..." and its body. At most one
// file part, at most 16 parts; a text field must be valid UTF-8 without
// control characters. Errc::invalid_argument saying what is wrong.
Result<UploadForm> parse_upload(std::string_view content_type, std::string_view body);

}  // namespace lmcfg::ui
