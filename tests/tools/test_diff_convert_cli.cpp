// convert is lossless for every fixture (diff's comparison itself:
// tests/ops/test_diff.cpp); stdin and oversized inputs; one UPID syntax; the --json
// reports validate against schemas/report-*.schema.json (real ajv).
#include <unistd.h>

#include <catch2/catch.hpp>
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <string>

#include "config/atomic_file.hpp"
#include "config/config_io.hpp"
#include "config/json_io.hpp"
#include "config/xml_io.hpp"
#include "db/database.hpp"
#include "db/value.hpp"
#include "ops/diff.hpp"
#include "test_config_support.hpp"

// This file's own namespace: the test binary is a unity build (tests/CMakeLists.txt).
namespace tools_test_diff_convert_cli {

using namespace lmcfg;
using namespace lmcfg::config;
using namespace lmcfg::config::testing;
namespace fs = std::filesystem;

namespace {

// A scratch directory of this file's tests.
struct Dir : test::ScratchDir {
  Dir() : test::ScratchDir("diffcli") {}
};

struct Out {
  int rc = -1;
  std::string out, err;
};

// Runs `lmcfg ARGS` through the shell, stdout and stderr captured.
Out tool(const Dir& d, const std::string& args) {
  const auto o = d.path / "stdout.txt", e = d.path / "stderr.txt";
  const std::string cmd =
      std::string(LMCFG_TOOL_PATH) + " " + args + " >'" + o.string() + "' 2>'" + e.string() + "'";
  const int rc = std::system(cmd.c_str());
  Out r;
  r.rc = WIFEXITED(rc) ? WEXITSTATUS(rc) : -1;
  r.out = slurp(o);
  r.err = slurp(e);
  return r;
}

std::string q(const fs::path& p) { return "'" + p.string() + "'"; }

Parameter typed(std::uint16_t upid, std::uint32_t value, std::uint8_t type) {
  Parameter p = param(upid, value);
  p.type = type;
  return p;
}

bool ajv_ready() {
  static const int ok = [] {
    return run("'" + (fs::path(LMCFG_SOURCE_DIR) / "scripts" / "install-node-deps.sh").string() +
               "'") == 0
               ? 1
               : 0;
  }();
  return ok == 1;
}

// Validates `json` against schemas/NAME with ajv; the validator's verdict.
bool valid_report(const Dir& d, const char* schema, const std::string& json) {
  const auto f = d.path / "report.json";
  spit(f, json);
  const auto ajv = fs::path(LMCFG_SOURCE_DIR) / "tools" / "node" / "node_modules" / ".bin" / "ajv";
  const auto s = fs::path(LMCFG_SOURCE_DIR) / "schemas" / schema;
  return run(q(ajv) + " validate --spec=draft2020 --strict=true -s " + q(s) + " -d " + q(f)) == 0;
}

}  // namespace

TEST_CASE("seed003 §12.1 command table entry name (off 38, \"Unnamed\") in the decoded view",
          "[config][convert]") {
  const auto j = must(write_json(golden_sinrise()));
  CHECK(j.find("\"decoded\": {\n        \"name\": \"Unnamed\"") != std::string::npos);
  const auto x = must(write_xml(golden_sinrise()));
  CHECK(x.find("<decoded name=\"Unnamed\"") != std::string::npos);
  Bytes odd = ct_entry2();
  odd[40] = 0x01;
  odd[41] = '\\';
  CHECK(ct_entry_name(odd) == "Un\\x01\\x5Cmed");
}

TEST_CASE(
    "convert: JSON -> XML -> JSON and XML -> JSON -> XML are byte-identical for every "
    "fixture",
    "[config][convert]") {
  Dir d;
  int n = 0;
  for (const auto& ent : fs::directory_iterator(fixture_dir())) {
    const auto ext = ent.path().extension();
    if (ext != ".json" && ext != ".xml") continue;
    DYNAMIC_SECTION(ent.path().filename().string()) {
      const auto j1 = d.path / "j1.json", x1 = d.path / "x1.xml", j2 = d.path / "j2.json",
                 x2 = d.path / "x2.xml";
      REQUIRE(tool(d, "convert --quiet " + q(ent.path()) + " " + q(j1)).rc == 0);
      REQUIRE(tool(d, "convert --quiet " + q(j1) + " " + q(x1)).rc == 0);
      REQUIRE(tool(d, "convert --quiet " + q(x1) + " " + q(j2)).rc == 0);
      REQUIRE(tool(d, "convert --quiet " + q(j2) + " " + q(x2)).rc == 0);
      CHECK(slurp(j2) == slurp(j1));
      CHECK(slurp(x2) == slurp(x1));
      // The command table's decoded views survive (name, and the command
      // through the UPID database).
      if (slurp(j1).find("\"raw\": [") != std::string::npos) {
        CHECK(slurp(j2).find("\"summary\"") != std::string::npos);
        CHECK(slurp(x2).find("summary=") != std::string::npos);
      }
    }
    ++n;
  }
  CHECK(n == 8);
}

TEST_CASE("convert and diff read standard input ('-'), format from the content",
          "[convert][diff]") {
  Dir d;
  const auto golden = fixture_dir() / "golden-sinrise.xml";
  const auto out = d.path / "from-stdin.json";
  auto c = tool(d, "convert --quiet - " + q(out) + " < " + q(golden));
  REQUIRE(c.rc == 0);
  CHECK(slurp(out).find("\"format_version\": 3") != std::string::npos);
  auto same =
      tool(d, "diff --quiet - " + q(fixture_dir() / "golden-sinrise.json") + " < " + q(golden));
  CHECK(same.rc == 0);
  CHECK(same.out.find("--- (stdin) (") == 0);
  auto both = tool(d, "diff --quiet - - < " + q(golden));
  CHECK(both.rc == 2);
  CHECK(both.err == "lmcfg diff: A and B are both standard input ('-'); at most one side can be\n");
  auto to_stdout = tool(d, "convert --quiet " + q(golden) + " - --to json");
  CHECK(to_stdout.rc == 0);
  CHECK(to_stdout.out == slurp(out));
}

TEST_CASE("inputs: endless streams and oversized files are refused up front", "[convert][diff]") {
  Dir d;
  auto z = tool(d, "diff --quiet defaults /dev/zero");
  CHECK(z.rc == 2);
  CHECK(z.err ==
        "lmcfg diff: /dev/zero: neither JSON nor XML (it starts with byte 00h); expected a "
        "configuration file (.json or .xml)\n");
  // A sparse file just over the limit: refused from its size, not read.
  const auto big = d.path / "big.json";
  { std::ofstream(big) << "{"; }
  fs::resize_file(big, kMaxInputBytes + 1);
  auto b = tool(d, "convert --quiet " + q(big) + " " + q(d.path / "o.xml"));
  CHECK(b.rc == 2);
  CHECK(b.err == "lmcfg convert: " + big.string() + ": " + std::to_string(kMaxInputBytes + 1) +
                     " bytes, larger than any configuration (at most 256 MiB)\n");
  // A stream over the limit (small limit here): refused when it passes it.
  auto s = read_text_file("/dev/zero", 1000);
  REQUIRE_FALSE(s.ok());
  CHECK(s.error().message ==
        "/dev/zero: more than 1000 bytes (an endless stream?); a configuration is far smaller");
}

TEST_CASE("one UPID syntax: 13A2, 13a2h, 0x13A2", "[db][cli]") {
  CHECK(*db::parse_upid("13A2") == 0x13A2);
  CHECK(*db::parse_upid("13a2h") == 0x13A2);
  CHECK(*db::parse_upid("0x13A2") == 0x13A2);
  CHECK(*db::parse_upid("F") == 0x000F);
  CHECK(db::parse_upid("13A2F").error().message ==
        "\"13A2F\" is not a UPID (expected up to 4 hex digits: 13A2, 13a2h or 0x13A2)");
  CHECK_FALSE(db::parse_upid("h").ok());
  CHECK_FALSE(db::parse_upid("0x").ok());
  Dir d;
  auto a = tool(d, "db show 13a2h");
  auto b = tool(d, "db show 0x13A2");
  CHECK(a.rc == 0);
  CHECK(a.out == b.out);
  CHECK(a.out.find("13A2") != std::string::npos);
}

TEST_CASE("reports: diff and convert --json validate against their documented shapes",
          "[diff][convert][schema]") {
  if (!ajv_ready()) FAIL("ajv unavailable: run scripts/install-node-deps.sh");
  Dir d;
  DriveConfig a, b;
  a.layer(2).push_back(typed(0x13A2, 70000, 3));
  b.layer(2).push_back(typed(0x13A2, 16, 4));
  b.scope.curves = false;
  const auto fa = d.path / "a.json", fb = d.path / "b.xml";
  REQUIRE(write_config_file(a, fa).ok());
  REQUIRE(write_config_file(b, fb).ok());
  auto r = tool(d, "diff --quiet --json " + q(fa) + " " + q(fb));
  CHECK(r.rc == 1);
  CHECK(r.out.find("\"a_invalid\":\"does not fit type UINT16\"") == std::string::npos);  // pretty
  CHECK(r.out.find("\"a_invalid\": \"does not fit type UINT16\"") != std::string::npos);
  CHECK(r.out.find("\"kind\": \"scope\"") != std::string::npos);
  CHECK(valid_report(d, "report-diff.schema.json", r.out));
  CHECK_FALSE(valid_report(d, "report-diff.schema.json", "{\"a\": 1}"));  // the schema bites
  // DeviceNet values, live values included.
  auto dn = devicenet_capture();
  dn.devicenet->values[0].raw = 7;
  dn.devicenet->live[0].raw = 9;
  const auto fd = d.path / "dn.json";
  REQUIRE(write_config_file(dn, fd).ok());
  auto n =
      tool(d, "diff --quiet --json --live " + q(fixture_dir() / "devicenet.json") + " " + q(fd));
  CHECK(n.rc == 1);
  CHECK(n.out.find("\"kind\": \"devicenet\"") != std::string::npos);
  CHECK(n.out.find("\"live\": true") != std::string::npos);
  CHECK(valid_report(d, "report-diff.schema.json", n.out));
  auto c = tool(d, "convert --quiet --json " + q(fixture_dir() / "everything.json") + " " +
                       q(d.path / "e.xml"));
  CHECK(c.rc == 0);
  CHECK(c.out.find("\"format\":\"xml\"") != std::string::npos);
  CHECK(valid_report(d, "report-convert.schema.json", c.out));
  auto cd = tool(d, "convert --quiet --json " + q(fixture_dir() / "devicenet.xml") + " " +
                        q(d.path / "dn.json"));
  CHECK(cd.rc == 0);
  CHECK(cd.out.find("\"devicenet_values\":4,\"devicenet_live\":2}") != std::string::npos);
  CHECK(valid_report(d, "report-convert.schema.json", cd.out));
}

TEST_CASE(
    "seed001 §4.3.110 db find searches descriptions: \"Maximal Current\" finds 13A6h and 13BAh",
    "[db][cli]") {
  Dir d;
  auto r = tool(d, "db find 'Maximal Current'");
  CHECK(r.rc == 0);
  CHECK(r.out.find("\n13A6 ") != std::string::npos);
  CHECK(r.out.find("\n13BA ") != std::string::npos);
}

TEST_CASE(
    "public parameter names: db show prints where a public name comes from and which family it was "
    "seen for",
    "[db][cli][families]") {
  Dir d;
  auto r = tool(d, "db show 13A6");
  CHECK(r.rc == 0);
  INFO(r.out);
  CHECK(r.out.find("Position controller maximal current (MAX_I)") != std::string::npos);
  CHECK(r.out.find("public: remcohn/linUDP linUDP.h (seen for: C1250 (constants named E1100_*); "
                   "LinUDP V2)") != std::string::npos);
  // A UPID only C1250 sources name: shown with its profile and provenance.
  auto run = tool(d, "db show 1450");
  CHECK(run.rc == 0);
  CHECK(run.out.find("c1250-mc-linudp") != std::string::npos);
  CHECK(run.out.find("public: Smart-Vision-Works/linmot_client") != std::string::npos);
}

}  // namespace tools_test_diff_convert_cli
