#include <catch2/catch.hpp>
#include <cstdlib>
#include <nlohmann/json.hpp>
#include <pugixml.hpp>

#include "config/config_io.hpp"
#include "config/json_io.hpp"
#include "config/xml_io.hpp"
#include "test_config_support.hpp"

// This file's own namespace: the test binary is a unity build (tests/CMakeLists.txt).
namespace config_test_config_io {

using namespace lmcfg;
using namespace lmcfg::config;
using namespace lmcfg::config::testing;
namespace fs = std::filesystem;

namespace {

struct FakeCtDecoder : CtEntryDecoder {
  std::optional<CtEntryView> decode(std::uint32_t id, ByteView raw) const override {
    if (id != 2) return std::nullopt;
    return CtEntryView{"VAI Go To Pos \"" + ct_entry_name(raw) + "\"",
                       {{"Position", "100", "mm"}, {"Velocity", "0.5", "m/s"}, {"Flag", "x", ""}}};
  }
};

// Golden files: compared byte for byte; LMCFG_UPDATE_GOLDEN=1 rewrites them.
void check_golden(const fs::path& path, const std::string& text) {
  if (std::getenv("LMCFG_UPDATE_GOLDEN")) spit(path, text);
  INFO(path.string());
  CHECK(slurp(path) == text);
}

}  // namespace

TEST_CASE("config: golden fixtures are what the writers produce", "[config]") {
  const auto cfg = golden_sinrise();
  check_golden(fixture_dir() / "golden-sinrise.json", must(write_json(cfg)));
  check_golden(fixture_dir() / "golden-sinrise.xml", must(write_xml(cfg)));
  const auto all = everything();
  FakeCtDecoder dec;
  WriteOptions opts;
  opts.ct_decoder = &dec;
  check_golden(fixture_dir() / "everything.json", must(write_json(all, opts)));
  check_golden(fixture_dir() / "everything.xml", must(write_xml(all, opts)));
}

TEST_CASE("config: golden fixtures read back to the seed configuration", "[config]") {
  for (const char* name : {"golden-sinrise.json", "golden-sinrise.xml"}) {
    INFO(name);
    auto cfg = must(read_config_file(fixture_dir() / name));
    CHECK(cfg == golden_sinrise());
    REQUIRE(cfg.curves.size() == 1);
    auto v = decode_curve(cfg.curves[0]);
    REQUIRE(v.ok());
    CHECK(v->name == "SinRise");
    CHECK(v->setpoints.size() == 21);
    CHECK(v->setpoints.back() == 1000000);
    CHECK(v->length == 100000);
    CHECK(v->length_ms_text() == "1000");
    REQUIRE(cfg.ct_entries.size() == 1);
    CHECK(cfg.ct_entries[0].id == 2);
    CHECK(cfg.ct_entries[0].raw.size() == 64);
    CHECK(ct_entry_name(cfg.ct_entries[0].raw) == "Unnamed");
    CHECK(cfg.find_param(0x13A2)->value == 16);
    CHECK(cfg.find_param(0x2076)->value == 0x11);
  }
  auto e = must(read_config_file(fixture_dir() / "everything.json"));
  CHECK(e == everything());
  CHECK(must(read_config_file(fixture_dir() / "everything.xml")) == everything());
}

TEST_CASE("config: JSON -> model -> XML -> model -> JSON is byte-identical for every fixture",
          "[config]") {
  FakeCtDecoder dec;
  WriteOptions opts;
  opts.ct_decoder = &dec;
  int n = 0;
  for (const auto& ent : fs::directory_iterator(fixture_dir())) {
    if (!ent.is_regular_file()) continue;
    const auto ext = ent.path().extension();
    if (ext != ".json" && ext != ".xml") continue;
    INFO(ent.path().string());
    ++n;
    auto m0 = must(read_config_file(ent.path()));
    const std::string j1 = must(write_json(m0, opts));
    auto m1 = must(read_json(j1, "j1"));
    CHECK(m1 == m0);
    const std::string x1 = must(write_xml(m1, opts));
    auto m2 = must(read_xml(x1, "x1"));
    CHECK(m2 == m0);
    const std::string j2 = must(write_json(m2, opts));
    CHECK(j2 == j1);
    CHECK(must(write_xml(must(read_json(j2, "j2")), opts)) == x1);
    // Two writes of the same model are byte-identical.
    CHECK(must(write_json(m0, opts)) == j1);
    CHECK(must(write_xml(m0, opts)) == x1);
  }
  CHECK(n >= 6);
}

TEST_CASE(
    "config: scope.drive_lacks round-trips through JSON and XML, and is written only when not "
    "empty",
    "[config]") {
  auto cfg = golden_sinrise();
  CHECK(must(write_json(cfg)).find("drive_lacks") == std::string::npos);
  CHECK(must(write_xml(cfg)).find("drive_lacks") == std::string::npos);
  cfg.curves.clear();
  cfg.ct_entries.clear();
  cfg.scope.curves = false;
  cfg.scope.command_table = false;
  cfg.scope.drive_lacks = {"curves", "command_table"};
  const std::string json = must(write_json(cfg));
  CHECK(nlohmann::json::parse(json)["scope"]["drive_lacks"] ==
        nlohmann::json::array({"curves", "command_table"}));
  CHECK(must(read_json(json, "j")) == cfg);
  const std::string xml = must(write_xml(cfg));
  pugi::xml_document doc;
  REQUIRE(doc.load_string(xml.c_str()));
  std::vector<std::string> groups;
  for (auto g : doc.document_element().child("scope").child("drive_lacks").children("group"))
    groups.push_back(g.text().get());
  CHECK(groups == cfg.scope.drive_lacks);
  CHECK(must(read_xml(xml, "x")) == cfg);
}

TEST_CASE("config: writers are canonical whatever the model order", "[config]") {
  auto a = everything();
  auto b = a;
  std::reverse(b.layer(3).begin(), b.layer(3).end());
  std::reverse(b.curves.begin(), b.curves.end());
  std::reverse(b.ct_entries.begin(), b.ct_entries.end());
  CHECK(must(write_json(a)) == must(write_json(b)));
  CHECK(must(write_xml(a)) == must(write_xml(b)));
  const auto j = must(write_json(b));
  CHECK(j.find("\"upid\": \"200E\"") < j.find("\"upid\": \"2076\""));
}

TEST_CASE("config: the writers show hex UPIDs, decimal values and scaled text", "[config]") {
  const auto j = must(write_json(everything()));
  CHECK(j.find("\"upid\": \"13A2\",\n") != std::string::npos);
  CHECK(j.find("\"value\": 16,\n") != std::string::npos);
  CHECK(j.find("\"scaled\": \"1.6\",\n") != std::string::npos);
  CHECK(j.find("\"unit\": \"A\"\n") != std::string::npos);
  CHECK(j.find("\"46 00 03 00 15 00 04 00 53 69 6E 52 69 73 65 00\",\n") != std::string::npos);
  CHECK(j.find("\"name\": \"SinRise\"") != std::string::npos);
  const auto x = must(write_xml(everything()));
  CHECK(x.find("<param upid=\"13A2\" value=\"16\" type=\"3\" name=\"Example &amp; &lt;name>\" "
               "scaled=\"1.6\" unit=\"A\" />") != std::string::npos);
  CHECK(x.find("<row>46 00 03 00 15 00 04 00 53 69 6E 52 69 73 65 00</row>") != std::string::npos);
  CHECK(x.rfind("<?xml version=\"1.0\" encoding=\"UTF-8\"?>\n", 0) == 0);
}

TEST_CASE("config: decoded views are derived and ignored on read", "[config]") {
  FakeCtDecoder dec;
  WriteOptions with;
  with.ct_decoder = &dec;
  WriteOptions without;
  without.include_decoded = false;
  const auto cfg = golden_sinrise();
  const auto j = must(write_json(cfg, with));
  CHECK(j.find("VAI Go To Pos \\\"Unnamed\\\"") != std::string::npos);
  const auto bare = must(write_json(cfg, without));
  CHECK(bare.find("decoded") == std::string::npos);
  CHECK(must(read_json(j, "j")) == must(read_json(bare, "b")));
  const auto x = must(write_xml(cfg, with));
  CHECK(x.find("<param name=\"Position\" value=\"100\" unit=\"mm\" />") != std::string::npos);
  CHECK(must(read_xml(x, "x")) == cfg);
}

TEST_CASE("config: writers refuse an invalid model", "[config]") {
  auto c = golden_sinrise();
  c.layer(3).push_back(param(0x2012, 1));
  auto r = write_json(c);
  REQUIRE_FALSE(r.ok());
  CHECK(r.error().code == make_error_code(Errc::validation_failed));
  CHECK_FALSE(write_xml(c).ok());
}

TEST_CASE("config: format selection", "[config]") {
  CHECK(*format_from_path("a/b.JSON") == FileFormat::json);
  CHECK(*format_from_path("b.xml") == FileFormat::xml);
  CHECK(format_from_path("b.txt").error().message ==
        "b.txt: cannot tell the format from the extension; expected .json or .xml (or give the "
        "format "
        "explicitly)");
  CHECK(*format_from_name("XML") == FileFormat::xml);
  CHECK_FALSE(format_from_name("yaml").ok());
  CHECK(sniff_format("  \n{") == FileFormat::json);
  CHECK(sniff_format("<?xml") == FileFormat::xml);
  CHECK_FALSE(sniff_format("hello"));
}

// --------------------------------------------------------------------------
// Hand-written bad fixtures: each rejected with an exact message.
TEST_CASE("config: bad fixtures are rejected with exact messages", "[config]") {
  std::size_t files = 0;
  for (const auto& ent : fs::directory_iterator(fixture_dir() / "bad"))
    if (ent.path().extension() == ".json" || ent.path().extension() == ".xml") ++files;
  CHECK(files == kBadCaseCount);
  for (std::size_t i = 0; i < kBadCaseCount; ++i) {
    const auto& bc = kBadCases[i];
    const fs::path p = fixture_dir() / "bad" / bc.file;
    const std::string text = slurp(p);
    REQUIRE_FALSE(text.empty());
    const std::string name = std::string("bad/") + bc.file;
    auto r = read_config_text(text, name, *format_from_path(p));
    INFO(name);
    REQUIRE_FALSE(r.ok());
    if (std::getenv("LMCFG_PRINT_MESSAGES")) std::printf("%s\n", r.error().message.c_str());
    CHECK(r.error().message == bc.message);
    CHECK(r.error().code == make_error_code(bc.code));
  }
}

}  // namespace config_test_config_io
