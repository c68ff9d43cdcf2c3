#include <unistd.h>

#include <catch2/catch.hpp>

#include "config/atomic_file.hpp"
#include "config/config_io.hpp"
#include "test_config_support.hpp"

// This file's own namespace: the test binary is a unity build (tests/CMakeLists.txt).
namespace config_test_config_files {

using namespace lmcfg;
using namespace lmcfg::config;
using namespace lmcfg::config::testing;
namespace fs = std::filesystem;

namespace {
struct TempDir {
  fs::path path;
  TempDir() {
    path = fs::temp_directory_path() /
           ("lmcfg-cfg-test-" + std::to_string(::getpid()) + "-" + std::to_string(counter()++));
    fs::remove_all(path);
    fs::create_directories(path);
  }
  ~TempDir() {
    std::error_code ec;
    fs::remove_all(path, ec);
  }
  static int& counter() {
    static int c = 0;
    return c;
  }
  std::size_t entries() const {
    std::size_t n = 0;
    for ([[maybe_unused]] const auto& e : fs::directory_iterator(path)) ++n;
    return n;
  }
};
}  // namespace

TEST_CASE("config: files round trip through write_config_file/read_config_file", "[config]") {
  TempDir d;
  for (const char* name : {"a.json", "a.xml"}) {
    const auto f = d.path / name;
    REQUIRE(write_config_file(everything(), f).ok());
    auto r = read_config_file(f);
    REQUIRE(r.ok());
    CHECK(*r == everything());
  }
  // Unknown extension: explicit format to write; sniffed to read.
  const auto t = d.path / "a.txt";
  CHECK_FALSE(write_config_file(everything(), t).ok());
  REQUIRE(write_config_file(everything(), t, FileFormat::xml).ok());
  CHECK(*read_config_file(t) == everything());
  auto nf = read_config_file(d.path / "missing.json");
  REQUIRE_FALSE(nf.ok());
  CHECK(nf.error().code == make_error_code(Errc::not_found));
  CHECK(read_config_file(d.path).error().message ==
        d.path.string() + ": is a directory; expected a file");
}

TEST_CASE("config: lmcfg convert", "[config]") {
  TempDir d;
  const std::string tool = LMCFG_TOOL_PATH;
  const auto golden = (fixture_dir() / "golden-sinrise.json").string();
  const auto x = d.path / "out.xml";
  REQUIRE(run(tool + " convert " + golden + " " + x.string()) == 0);
  // convert adds the database's decoded command (the fixtures are written
  // without a decoder): otherwise the same document.
  CHECK(slurp(x).find("<decoded name=\"Unnamed\" summary=\"") != std::string::npos);
  CHECK(*read_config_file(x) == *read_config_file(fixture_dir() / "golden-sinrise.xml"));
  const auto j = d.path / "back.json";
  REQUIRE(run(tool + " convert " + x.string() + " " + j.string()) == 0);
  CHECK(*read_config_file(j) == *read_config_file(golden));
  CHECK(slurp(j).find("\"summary\": \"") != std::string::npos);
  const auto t = d.path / "explicit.cfg";
  REQUIRE(run(tool + " convert " + golden + " " + t.string() + " --to xml") == 0);
  CHECK(slurp(t) == slurp(x));
  // v1 in, v3 out.
  const auto m = d.path / "migrated.json";
  REQUIRE(run(tool + " convert " + (fixture_dir() / "v1-sinrise.xml").string() + " " +
              m.string()) == 0);
  CHECK(slurp(m).find("\"format_version\": 3") != std::string::npos);
  // Invalid input: exit 2, nothing written.
  const auto none = d.path / "none.json";
  CHECK(run(tool + " convert " + (fixture_dir() / "bad" / "json-dup-upid.json").string() + " " +
            none.string()) == 2);
  CHECK_FALSE(fs::exists(none));
  CHECK(run(tool + " convert " + golden + " " + (d.path / "x.cfg").string()) == 2);
  CHECK(run(tool + " convert " + golden + " " + none.string() + " --to yaml") == 2);
  CHECK(run(tool + " convert " + golden + " " + d.path.string() + " --to json") == 2);
  CHECK_FALSE(fs::exists(none));
}

}  // namespace config_test_config_files
