// The XML reader and writer (xml_io.cpp, xml_write.cpp, xml_fields.cpp,
// xml_read_v1.cpp): the document's frame and each kind of field, with the
// exact located messages.
#include <catch2/catch.hpp>

#include "config/xml_io.hpp"
#include "test_config_support.hpp"

// This file's own namespace: the test binary is a unity build (tests/CMakeLists.txt).
namespace config_test_xml_io {

using namespace lmcfg;
using namespace lmcfg::config;
using namespace lmcfg::config::testing;

namespace {

const std::string kScope =
    "layers=\"2\" parameters=\"modified\" curves=\"true\" command_table=\"true\"";
const std::string kParam = "<param upid=\"13A2\" value=\"16\"/>";

// A small document: the attributes of <scope>, the parameters of layer 2, and
// elements before <scope>.
std::string doc(const std::string& scope = kScope, const std::string& params = kParam,
                const std::string& more = "", const std::string& version = "3") {
  return "<lmcfg format=\"lmcfg-drive-config\" format_version=\"" + version + "\">" + more +
         "<scope " + scope + "/><parameters><layer number=\"2\">" + params +
         "</layer></parameters></lmcfg>";
}

std::string message(const std::string& text) {
  auto r = read_xml(text, "t.xml");
  REQUIRE_FALSE(r.ok());
  return r.error().message;
}

const std::string kDevicenetScope =
    "layers=\"\" parameters=\"modified\" curves=\"false\" command_table=\"false\"";

}  // namespace

TEST_CASE("xml_io: a small document reads, and writes every layer and element", "[config][xml]") {
  const auto cfg = must(read_xml(doc(), "t.xml"));
  REQUIRE(cfg.layer(2).size() == 1);
  CHECK(cfg.layer(2)[0].value == 16);
  const auto text = must(write_xml(cfg));
  CHECK(text.find("  <identity>\n    <macid />\n    <link port=\"\" baud=\"\" parity=\"\" "
                  "stop_bits=\"\" checksum=\"\" />\n    <product />") != std::string::npos);
  CHECK(text.find("<upid_db version=\"\" hash=\"\" />\n    <captured_at />\n    <labels />\n  "
                  "</identity>") != std::string::npos);
  CHECK(text.find("<scope layers=\"2\" parameters=\"modified\" curves=\"true\" "
                  "command_table=\"true\" />") != std::string::npos);
  CHECK(text.find("<layer number=\"4\" name=\"Appl\" />\n  </parameters>\n  <curves />\n  "
                  "<command_table />\n</lmcfg>\n") != std::string::npos);
}

TEST_CASE("xml_io: each kind of field says what it expected, and where", "[config][xml]") {
  CHECK(message(doc(kScope, "<param upid=\"13G2\" value=\"1\"/>")) ==
        "t.xml: /lmcfg/parameters/layer[1]/param[1]/@upid: expected a UPID as 4 hex digits "
        "(\"13A2\"), found \"13G2\"");
  CHECK(message(doc(kScope,
                    "<param upid=\"13A2\" value=\"1\"/><param upid=\"13A3\" value=\"1\" "
                    "type=\"16\"/>")) ==
        "t.xml: /lmcfg/parameters/layer[1]/param[2]/@type: expected a type code (0..15 in "
        "decimal), found \"16\"");
  CHECK(message(doc("layers=\"2 2\" parameters=\"modified\" curves=\"true\" "
                    "command_table=\"true\"")) ==
        "t.xml: /lmcfg/scope/@layers: layer 2 listed twice");
  CHECK(message(doc("layers=\"5\" parameters=\"modified\" curves=\"true\" "
                    "command_table=\"true\"")) ==
        "t.xml: /lmcfg/scope/@layers: expected layer numbers 1..4 separated by spaces, found "
        "\"5\"");
  CHECK(message(doc("layers=\"2\" parameters=\"all\" curves=\"true\" command_table=\"true\"")) ==
        "t.xml: /lmcfg/scope/@parameters: expected \"modified\" or \"full\", found \"all\"");
  CHECK(message(doc("layers=\"2\" parameters=\"full\" command_table=\"true\"")) ==
        "t.xml: /lmcfg/scope: missing attribute \"curves\"");
  CHECK(message(doc(kScope, kParam,
                    "<identity><labels><label key=\"a\">1</label><label key=\"a\">2</label>"
                    "</labels></identity>")) ==
        "t.xml: /lmcfg/identity/labels/label[2]/@key: duplicate label \"a\"");
  CHECK(message(doc(kScope, kParam, "<identity><link port=\"x\" speed=\"1\"/></identity>")) ==
        "t.xml: /lmcfg/identity/link/@speed: unexpected attribute; expected one of: port, baud, "
        "parity, stop_bits, checksum");
  CHECK(message(doc(kScope, kParam, "<identity><macid>1<b/></macid></identity>")) ==
        "t.xml: /lmcfg/identity/macid/b: unexpected element; expected text only");
  CHECK(message(doc(kScope, kParam, "<identity><product/><product/></identity>")) ==
        "t.xml: /lmcfg/identity/product: element <product> appears twice");
  CHECK(message(doc(kScope, kParam,
                    "<curves><curve id=\"1\"><info><row>46 00</row></info></curve>"
                    "</curves>")) == "t.xml: /lmcfg/curves/curve[1]: missing element <data>");
}

TEST_CASE("xml_io: the devicenet section's kinds, and its format version", "[config][xml]") {
  const auto dn = [&](const std::string& section, const std::string& version = "3") {
    return "<lmcfg format=\"lmcfg-drive-config\" format_version=\"" + version + "\"><scope " +
           kDevicenetScope + "/><parameters/>" + section + "</lmcfg>";
  };
  const std::string ok =
      "<devicenet can_bitrate=\"125000\" motors=\"A\"><values><value motor=\"A\" "
      "command=\"34\" raw=\"1\"/></values></devicenet>";
  CHECK(must(read_xml(dn(ok), "t.xml")).devicenet->values.at(0).command == 0x34);
  CHECK(message(dn("<devicenet can_bitrate=\"125000\" motors=\"A E\"/>")) ==
        "t.xml: /lmcfg/devicenet/@motors: expected motors A..D separated by spaces, found \"A "
        "E\"");
  CHECK(message(dn("<devicenet can_bitrate=\"125000\" motors=\"A\"><values><value motor=\"0\" "
                   "command=\"34\" raw=\"1\"/></values></devicenet>")) ==
        "t.xml: /lmcfg/devicenet/values/value[1]/@motor: expected \"controller\" or a motor "
        "\"A\"..\"D\", found \"0\"");
  CHECK(message(dn("<devicenet can_bitrate=\"125000\" motors=\"A\"><live><value motor=\"A\" "
                   "command=\"134\" raw=\"1\"/></live></devicenet>")) ==
        "t.xml: /lmcfg/devicenet/live/value[1]/@command: expected a command ID as 2 hex digits "
        "(\"34\"), found \"134\"");
  CHECK(message(dn("<devicenet can_bitrate=\"125000\" motors=\"A\"><io_modules><mod/>"
                   "</io_modules></devicenet>")) ==
        "t.xml: /lmcfg/devicenet/io_modules/mod: unexpected element; expected one of: module");
  CHECK(message(dn(ok, "2")) ==
        "t.xml: /lmcfg/devicenet: unexpected element; the devicenet section is new in "
        "format_version 3, this file says 2");
}

}  // namespace config_test_xml_io
