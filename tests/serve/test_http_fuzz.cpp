// The HTTP fuzz target's entry (fuzz/fuzz_http_entry.hpp) in the normal test
// suite: its seed requests (tests/fixtures/fuzz-http/) and every input it ever
// failed on (tests/fixtures/fuzz-regressions/http/) are replayed here, built
// with gcc (and under the sanitizers in the LMCFG_SANITIZE build). A
// regression aborts the run (http_fail) or trips a sanitizer.
#include <algorithm>
#include <catch2/catch.hpp>
#include <filesystem>
#include <fstream>
#include <iterator>

#include "../../fuzz/fuzz_http_entry.hpp"

// This file's own namespace: the test binary is a unity build (tests/CMakeLists.txt).
namespace serve_test_http_fuzz {

using namespace lmcfg;
namespace fs = std::filesystem;

namespace {

std::size_t replay_dir(const fs::path& dir) {
  std::vector<fs::path> files;
  std::error_code ec;
  if (fs::is_directory(dir, ec))
    for (const auto& e : fs::directory_iterator(dir))
      if (e.is_regular_file() && e.path().extension() != ".md") files.push_back(e.path());
  std::sort(files.begin(), files.end());
  for (const auto& p : files) {
    INFO(p.string());
    std::ifstream in(p, std::ios::binary);
    const std::string b((std::istreambuf_iterator<char>(in)), std::istreambuf_iterator<char>());
    fuzz::http_entry(reinterpret_cast<const std::uint8_t*>(b.data()), b.size());
  }
  return files.size();
}

}  // namespace

TEST_CASE("fuzz regressions: raw HTTP requests into lmcfg serve", "[serve][fuzz]") {
  const fs::path root = fs::path(LMCFG_SOURCE_DIR) / "tests/fixtures";
  CHECK(replay_dir(root / "fuzz-http") >= 30);
  replay_dir(root / "fuzz-regressions/http");
  // The seeds reach the routes: a GET of the drives is answered 200 with JSON.
  static fuzz::HttpTarget t(false);
  const std::string a =
      t.http->answer("GET /api/v1/drives HTTP/1.1\r\nHost: fuzz\r\n\r\n", "127.0.0.1", false);
  CHECK(a.rfind("HTTP/1.1 200 OK\r\n", 0) == 0);
  CHECK(a.find("\"name\": \"press3/z\"") != std::string::npos);
  // Pipelined: three answers; a refused request ends the connection's answers.
  const std::string three = t.http->answer(
      "GET /console.css HTTP/1.1\r\nHost: fuzz\r\n\r\nHEAD /metrics HTTP/1.1\r\nHost: fuzz\r\n\r\n"
      "GET /%FF HTTP/1.1\r\nHost: fuzz\r\n\r\nGET / HTTP/1.1\r\nHost: fuzz\r\n\r\n",
      "127.0.0.1", false);
  CHECK(std::count(three.begin(), three.end(), 'H') >= 3);
  CHECK(three.find("HTTP/1.1 400 Bad Request\r\n") != std::string::npos);
  CHECK(three.rfind("HTTP/1.1 ") == three.find("HTTP/1.1 400"));
}

}  // namespace serve_test_http_fuzz
