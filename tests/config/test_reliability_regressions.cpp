// docs/reliability.md: every input a fuzz target ever failed on
// (tests/fixtures/fuzz-regressions/<target>/) is fed to the same entry point
// (fuzz/fuzz_entries.hpp) in the normal test suite, built with gcc. A regression aborts the run
// (fuzz_fail) or trips the sanitizers in the LMCFG_SANITIZE build.
#include <catch2/catch.hpp>
#include <filesystem>
#include <fstream>
#include <iterator>

#include "../../fuzz/fuzz_entries.hpp"
#include "config/config_io.hpp"

// This file's own namespace: the test binary is a unity build (tests/CMakeLists.txt).
namespace config_test_reliability_regressions {

using namespace lmcfg;
namespace fs = std::filesystem;

namespace {

std::vector<fs::path> regression_inputs(const std::string& target) {
  std::vector<fs::path> out;
  const fs::path dir = fs::path(LMCFG_SOURCE_DIR) / "tests/fixtures/fuzz-regressions" / target;
  std::error_code ec;
  if (!fs::is_directory(dir, ec)) return out;
  for (const auto& e : fs::directory_iterator(dir)) {
    if (e.is_regular_file() && e.path().extension() != ".md") out.push_back(e.path());
  }
  std::sort(out.begin(), out.end());
  return out;
}

Bytes slurp(const fs::path& p) {
  std::ifstream in(p, std::ios::binary);
  return Bytes((std::istreambuf_iterator<char>(in)), std::istreambuf_iterator<char>());
}

template <class Entry>
std::size_t replay(const std::string& target, Entry entry) {
  std::size_t n = 0;
  for (const auto& p : regression_inputs(target)) {
    INFO(p.string());
    const Bytes b = slurp(p);
    entry(b.data(), b.size());
    ++n;
  }
  return n;
}

}  // namespace

TEST_CASE("fuzz regressions: telegram stream decoder", "[reliability][fuzz]") {
  const auto n = replay("decoder", fuzz::decoder_entry);
  // A few hand-made edge cases run every time, whatever the folder holds.
  const std::vector<Bytes> edge{
      {},
      {0x00, 0x00},
      {0x01, 0x05, 0x01, 0x11, 0x3F, 0x02},                          // LEN 63, nothing follows
      {0x00, 0x01, 0x01, 0x01, 0x01, 0x01, 0x01, 0x01, 0x01, 0x01},  // only start bytes
      {0x02, 0x00, 0x01, 0x11, 0x03, 0x02, 0x00, 0x00, 0x00, 0x00,
       0x04},  // checksum mode, no checksum bytes
  };
  for (const auto& b : edge) fuzz::decoder_entry(b.data(), b.size());
  SUCCEED(std::to_string(n) + " regression input(s)");
}

// fuzz_json_config found that a number too large for a double (e.g. 300 digits)
// made nlohmann::json throw out_of_range.406 out of config::read_config_text;
// the reader now reports it as a parse error with its position.
TEST_CASE("fuzz regressions: JSON configuration reader", "[reliability][fuzz]") {
  const auto n = replay("json_config", fuzz::json_entry);
  for (const std::string& s : std::vector<std::string>{"", "{", "[]", "{\"format\": 1e999}",
                                                       "\xEF\xBB\xBF{}", std::string(64, '[')}) {
    fuzz::json_entry(reinterpret_cast<const std::uint8_t*>(s.data()), s.size());
  }
  SUCCEED(std::to_string(n) + " regression input(s)");
}

TEST_CASE("fuzz regressions: XML configuration reader", "[reliability][fuzz]") {
  const auto n = replay("xml_config", fuzz::xml_entry);
  for (const std::string& s : std::vector<std::string>{
           "", "<", "<lmcfg/>", "<?xml version=\"1.0\"?><lmcfg format_version=\"99\"/>",
           "<!DOCTYPE x [<!ENTITY a \"aaaa\">]><lmcfg>&a;</lmcfg>"}) {
    fuzz::xml_entry(reinterpret_cast<const std::uint8_t*>(s.data()), s.size());
  }
  SUCCEED(std::to_string(n) + " regression input(s)");
}

TEST_CASE("fuzz regressions: client answer handling", "[reliability][fuzz]") {
  const auto n = replay("client", fuzz::client_entry);
  // Every operation against silence, and against a stream of start bytes.
  for (std::uint8_t op = 0; op < 12; ++op) {
    Bytes silence{op, 0};
    fuzz::client_entry(silence.data(), silence.size());
    Bytes starts{op, 1};
    starts.resize(200, 0x01);
    fuzz::client_entry(starts.data(), starts.size());
  }
  SUCCEED(std::to_string(n) + " regression input(s)");
}

TEST_CASE("a JSON number no double can hold is a parse error with its position",
          "[reliability][config]") {
  auto r =
      config::read_config_text("{\n  \"format\": 1e999\n}\n", "big.json", config::FileFormat::json);
  REQUIRE_FALSE(r.ok());
  CHECK(r.error().code == Errc::parse_error);
  CHECK(r.error().message ==
        "big.json:2:13: number 1e999 is out of range (expected an integer value field)");
}

}  // namespace config_test_reliability_regressions
