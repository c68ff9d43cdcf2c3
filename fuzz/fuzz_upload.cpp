// libFuzzer target: lmcfg ui's multipart/form-data reader (ui/upload.hpp),
// the part of the technician's page that takes a whole file from a client.
// The input's first line is the Content-Type header value, the rest the body.
// It must return (a form or an error) for any input; a form it returns keeps
// its promises: at most 16 fields, text fields one line of UTF-8, no file
// without its field's name, nothing larger than the body it came from.
#include <cstdint>
#include <cstdio>
#include <cstdlib>
#include <string_view>

#include "common/text.hpp"
#include "ui/upload.hpp"

namespace {

[[noreturn]] void fail(const char* what) {
  std::fprintf(stderr, "fuzz invariant violated: %s\n", what);
  std::abort();
}

}  // namespace

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  const std::string_view input(reinterpret_cast<const char*>(data), size);
  const auto eol = input.find('\n');
  const std::string_view type = input.substr(0, eol);
  const std::string_view body =
      eol == std::string_view::npos ? std::string_view() : input.substr(eol + 1);
  auto form = lmcfg::ui::parse_upload(type, body);
  if (!form.ok()) {
    if (form.error().message.empty()) fail("an error without a message");
    return 0;
  }
  if (form->fields.size() > 16) fail("more than 16 fields");
  for (const auto& [name, value] : form->fields)
    if (!lmcfg::valid_utf8(value) || lmcfg::control_at(value) != std::string_view::npos)
      fail("a text field that is not one line of UTF-8");
  if (!form->file.empty() && form->file_field.empty()) fail("a file without its field");
  if (form->file.size() > body.size()) fail("a file larger than the body");
  return 0;
}
