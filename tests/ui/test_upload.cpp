// ui/upload.hpp: the drive page's file form taken apart as a browser sends
// it (multipart/form-data), and what is refused.
#include <catch2/catch.hpp>
#include <filesystem>
#include <fstream>
#include <sstream>

#include "ui/upload.hpp"

namespace ui_test_upload {

using namespace lmcfg;

const char* kType = "multipart/form-data; boundary=----WebKitFormBoundaryAb12";

std::string part(const std::string& disposition, const std::string& content) {
  return "------WebKitFormBoundaryAb12\r\nContent-Disposition: " + disposition + "\r\n\r\n" +
         content + "\r\n";
}

const std::string kEnd = "------WebKitFormBoundaryAb12--\r\n";

TEST_CASE("upload: the fields and the file, as Chromium sends them", "[ui_upload]") {
  const std::string body =
      part("form-data; name=\"csrf\"", "c5rf") + part("form-data; name=\"key\"", "sim__x-11h") +
      "------WebKitFormBoundaryAb12\r\nContent-Disposition: form-data; name=\"file\"; "
      "filename=\"axis %22one%22.json\"\r\nContent-Type: application/json\r\n\r\n{\r\n\"a\": "
      "1}\r\n\r\n" +
      part("form-data; name=\"then\"", "plan") + kEnd;
  auto up = ui::parse_upload(kType, body);
  REQUIRE(up.ok());
  CHECK(up->fields.at("csrf") == "c5rf");
  CHECK(up->fields.at("key") == "sim__x-11h");
  CHECK(up->fields.at("then") == "plan");
  CHECK(up->file_field == "file");
  CHECK(up->file_name == "axis %22one%22.json");
  CHECK(up->file == "{\r\n\"a\": 1}\r\n");  // the file's own line breaks kept
}

TEST_CASE("upload: a quoted boundary, a file name with a backslash kept as sent", "[ui_upload]") {
  const std::string body =
      "--b c\r\nContent-Disposition: form-data; name=\"file\"; "
      "filename=\"C:\\x.json\"\r\n\r\n{}\r\n--b c--";
  auto up = ui::parse_upload("Multipart/Form-Data; charset=utf-8; boundary=\"b c\"", body);
  REQUIRE(up.ok());
  CHECK(up->file_name == "C:\\x.json");
  CHECK(up->file == "{}");
}

TEST_CASE("upload: what is refused, and why", "[ui_upload]") {
  const auto refused = [](const std::string& type, const std::string& body) {
    auto up = ui::parse_upload(type, body);
    REQUIRE_FALSE(up.ok());
    CHECK(up.error().code == Errc::invalid_argument);
    return up.error().message;
  };
  const std::string how = "): choose the file again on the drive's page and send it from there";
  CHECK(refused("application/x-www-form-urlencoded", "a=1") ==
        "a file must be sent as multipart/form-data");
  CHECK(refused("multipart/form-data", "") ==
        "the upload is not a form the page sends (no boundary of 1 to 70 characters" + how);
  CHECK(refused(kType, "--other\r\n") ==
        "the upload is not a form the page sends (no first boundary" + how);
  CHECK(refused(kType, part("form-data; name=\"a\"", "x")) ==
        "the upload is not a form the page sends (no closing boundary" + how);
  CHECK(refused(kType, part("attachment; name=\"a\"", "x") + kEnd) ==
        "the upload is not a form the page sends (a part that is not form-data" + how);
  CHECK(refused(kType, part("form-data; filename=\"a.json\"", "x") + kEnd) ==
        "the upload is not a form the page sends (a part without a field name" + how);
  CHECK(refused(kType, part("form-data; name=\"f\"; filename=\"a.json\"", "x") +
                           part("form-data; name=\"g\"; filename=\"b.json\"", "y") + kEnd) ==
        "the upload is not a form the page sends (more than one file" + how);
  CHECK(refused(kType, part("form-data; name=\"key\"", "a\nb") + kEnd) ==
        "the upload is not a form the page sends (the field 'key' is not one line of UTF-8" + how);
  std::string many;
  for (int i = 0; i < 17; ++i) many += part("form-data; name=\"f" + std::to_string(i) + "\"", "x");
  CHECK(refused(kType, many + kEnd) ==
        "the upload is not a form the page sends (more than 16 parts" + how);
}

// The fuzz target's seeds and every input it ever failed on
// (fuzz/fuzz_upload.cpp: the first line the Content-Type, the rest the
// body), read again here with gcc: each gives a form or an error.
TEST_CASE("upload: the fuzz target's seeds and regressions read back", "[ui_upload]") {
  namespace fs = std::filesystem;
  std::size_t inputs = 0;
  for (const char* dir : {"tests/fixtures/fuzz-upload", "tests/fixtures/fuzz-regressions/upload"}) {
    const fs::path at = fs::path(LMCFG_SOURCE_DIR) / dir;
    if (!fs::exists(at)) continue;
    for (const auto& e : fs::directory_iterator(at)) {
      if (!e.is_regular_file() || e.path().extension() == ".md") continue;
      std::ifstream in(e.path(), std::ios::binary);
      std::stringstream text;
      text << in.rdbuf();
      const std::string input = text.str();
      const auto eol = input.find('\n');
      const std::string type = input.substr(0, eol);
      const std::string body = eol == std::string::npos ? "" : input.substr(eol + 1);
      INFO(e.path().string());
      const auto form = ui::parse_upload(type, body);
      CHECK((form.ok() || !form.error().message.empty()));
      ++inputs;
    }
  }
  CHECK(inputs >= 1);
  // The seed is a form the page sends: its file comes out whole.
  std::ifstream in(fs::path(LMCFG_SOURCE_DIR) / "tests/fixtures/fuzz-upload/two-parts",
                   std::ios::binary);
  std::stringstream text;
  text << in.rdbuf();
  const std::string seed = text.str();
  const auto form =
      ui::parse_upload(seed.substr(0, seed.find('\n')), seed.substr(seed.find('\n') + 1));
  REQUIRE(form.ok());
  CHECK(form->file_name == "axis.json");
  CHECK(form->file == "{\"format\": \"lmcfg-drive-config\"}");
  CHECK(form->fields.at("csrf") == "ABC");
}

}  // namespace ui_test_upload
