// multipart/form-data as browsers send a form with a file (ui/upload.hpp):
// RFC 7578 over RFC 2046 §5.1.1's framing. Only what a browser's form
// sends is taken: parts named by Content-Disposition "form-data", one file.
#include "ui/upload.hpp"

#include <cctype>

#include "common/text.hpp"

namespace lmcfg::ui {

namespace {

constexpr std::size_t kMaxParts = 16;

Error bad_upload(const std::string& what) {
  return Error(Errc::invalid_argument,
               "the upload is not a form the page sends (" + what +
                   "): choose the file again on the drive's page and send it from there");
}

std::string lower_ascii(std::string_view s) {
  std::string o(s);
  for (char& c : o) c = static_cast<char>(std::tolower(static_cast<unsigned char>(c)));
  return o;
}

std::string_view trim_ws(std::string_view s) {
  while (!s.empty() && (s.front() == ' ' || s.front() == '\t')) s.remove_prefix(1);
  while (!s.empty() && (s.back() == ' ' || s.back() == '\t')) s.remove_suffix(1);
  return s;
}

// The parameter `name` of a header value ("form-data; name=\"key\"";
// "multipart/form-data; boundary=x"): its value unquoted, nullopt when
// absent. No backslash escapes: browsers write a quote in a file name as
// "%22" and leave a backslash as it is (HTML "multipart/form-data encoding
// algorithm"; RFC 7578 §4.2), which the name check then refuses.
std::optional<std::string> header_param(std::string_view value, std::string_view name) {
  std::size_t pos = value.find(';');
  while (pos != std::string_view::npos) {
    std::string_view rest = trim_ws(value.substr(pos + 1));
    const auto eq = rest.find('=');
    if (eq == std::string_view::npos) return std::nullopt;
    const std::string key = lower_ascii(trim_ws(rest.substr(0, eq)));
    std::string_view v = rest.substr(eq + 1);
    std::string out;
    std::size_t used = 0;
    if (!v.empty() && v.front() == '"') {
      std::size_t i = 1;
      for (; i < v.size() && v[i] != '"'; ++i) out += v[i];
      if (i >= v.size()) return std::nullopt;  // an unclosed quote
      used = i + 1;
    } else {
      // By hand, not find(): MinGW's GCC 12 at -O2 warns (an error with
      // -Werror) of a memchr bound it cannot see is the view's size.
      while (used < v.size() && v[used] != ';') ++used;
      out = std::string(trim_ws(v.substr(0, used)));
    }
    if (key == name) return out;
    std::size_t next = used;
    while (next < v.size() && v[next] != ';') ++next;
    if (next >= v.size()) return std::nullopt;  // no other parameter
    pos = static_cast<std::size_t>(v.data() + next - value.data());
  }
  return std::nullopt;
}

// One part's headers and content; `form` gets it.
Result<void> take_part(std::string_view part, UploadForm& form) {
  const auto head_end = part.find("\r\n\r\n");
  if (head_end == std::string_view::npos) return bad_upload("a part without headers");
  std::string_view head = part.substr(0, head_end);
  const std::string_view content = part.substr(head_end + 4);
  std::optional<std::string> name, file_name;
  while (!head.empty()) {
    const auto eol = head.find("\r\n");
    const std::string_view line = head.substr(0, eol);
    head = eol == std::string_view::npos ? std::string_view() : head.substr(eol + 2);
    const auto colon = line.find(':');
    if (colon == std::string_view::npos) return bad_upload("a malformed part header");
    if (lower_ascii(trim_ws(line.substr(0, colon))) != "content-disposition") continue;
    const std::string_view value = trim_ws(line.substr(colon + 1));
    if (lower_ascii(value.substr(0, value.find(';'))) != "form-data")
      return bad_upload("a part that is not form-data");
    name = header_param(value, "name");
    file_name = header_param(value, "filename");
  }
  if (!name || name->empty()) return bad_upload("a part without a field name");
  if (file_name) {
    if (!form.file_field.empty()) return bad_upload("more than one file");
    form.file_field = *name;
    form.file_name = *file_name;
    form.file = std::string(content);
    return {};
  }
  if (!valid_utf8(content) || control_at(content) != std::string_view::npos)
    return bad_upload("the field '" + one_line(*name) + "' is not one line of UTF-8");
  form.fields[*name] = std::string(content);
  return {};
}

}  // namespace

Result<UploadForm> parse_upload(std::string_view content_type, std::string_view body) {
  if (lower_ascii(trim_ws(content_type.substr(0, content_type.find(';')))) != "multipart/form-data")
    return Error(Errc::invalid_argument, "a file must be sent as multipart/form-data");
  const auto boundary = header_param(content_type, "boundary");
  if (!boundary || boundary->empty() || boundary->size() > 70)  // RFC 2046 §5.1.1
    return bad_upload("no boundary of 1 to 70 characters");
  const std::string delimiter = "--" + *boundary;
  if (body.substr(0, delimiter.size()) != delimiter) return bad_upload("no first boundary");
  UploadForm form;
  std::size_t pos = delimiter.size(), parts = 0;
  for (;;) {
    if (body.substr(pos, 2) == "--") return form;  // the close delimiter
    if (body.substr(pos, 2) != "\r\n") return bad_upload("a boundary not ending its line");
    pos += 2;
    const auto next = body.find("\r\n" + delimiter, pos);
    if (next == std::string_view::npos) return bad_upload("no closing boundary");
    if (++parts > kMaxParts) return bad_upload("more than 16 parts");
    LMCFG_TRY(take_part(body.substr(pos, next - pos), form));
    pos = next + 2 + delimiter.size();
  }
}

}  // namespace lmcfg::ui
