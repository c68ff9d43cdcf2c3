// The `devicenet` section (format version 3, seed 000 controllers): both
// writers and readers, exact messages with their place in the file, and
// version 2 files without the section.
#include <catch2/catch.hpp>

#include "config/config_io.hpp"
#include "config/json_io.hpp"
#include "config/xml_io.hpp"
#include "test_config_support.hpp"

// This file's own namespace: the test binary is a unity build (tests/CMakeLists.txt).
namespace config_test_config_devicenet {

using namespace lmcfg;
using namespace lmcfg::config;
using namespace lmcfg::config::testing;

namespace {

std::string replaced(std::string s, const std::string& from, const std::string& to) {
  const auto at = s.find(from);
  REQUIRE(at != std::string::npos);
  return s.replace(at, from.size(), to);
}

// A small DeviceNet document; `values` is the body of its values array (line 6 on).
std::string json_doc(const std::string& section_head, const std::string& values) {
  return "{\"format\": \"lmcfg-drive-config\", \"format_version\": 3,\n"
         " \"scope\": {\"layers\": [], \"parameters\": \"modified\", \"curves\": false, "
         "\"command_table\": false},\n"
         " \"parameters\": [],\n"
         " \"devicenet\": {" +
         section_head +
         ",\n"
         "  \"values\": [\n" +
         values + "\n  ]}}\n";
}
const std::string kHead = "\"can_bitrate\": 125000, \"motors\": [\"A\"]";

std::string xml_doc(const std::string& attrs, const std::string& values) {
  return "<lmcfg format=\"lmcfg-drive-config\" format_version=\"3\">"
         "<scope layers=\"\" parameters=\"modified\" curves=\"false\" command_table=\"false\"/>"
         "<parameters/><devicenet " +
         attrs + "><values>" + values + "</values></devicenet></lmcfg>";
}
const std::string kAttrs = "can_bitrate=\"125000\" motors=\"A\"";

struct Expect {
  Errc code;
  std::string message;
};
void check_error(const Result<DriveConfig>& r, const Expect& e) {
  REQUIRE_FALSE(r.ok());
  CHECK(r.error().message == e.message);
  CHECK(r.error().code == make_error_code(e.code));
}

}  // namespace

TEST_CASE("config: the devicenet section round trips in both formats", "[config][devicenet]") {
  const auto cfg = devicenet_capture();
  const auto j = must(write_json(cfg));
  CHECK(must(read_json(j, "j")) == cfg);
  const auto x = must(write_xml(cfg));
  CHECK(must(read_xml(x, "x")) == cfg);
  CHECK(must(write_json(must(read_xml(x, "x")))) == j);
  CHECK(must(write_xml(must(read_json(j, "j")))) == x);
  // Canonical whatever the model order; the controller's values first.
  auto shuffled = cfg;
  std::reverse(shuffled.devicenet->values.begin(), shuffled.devicenet->values.end());
  std::reverse(shuffled.devicenet->motors.begin(), shuffled.devicenet->motors.end());
  CHECK(must(write_json(shuffled)) == j);
  CHECK(j.find("\"format_version\": 3,") != std::string::npos);
  CHECK(j.find("      {\n        \"motor\": \"controller\",\n        \"command\": \"02\",\n"
               "        \"raw\": 3,\n        \"name\": \"Get Status Low Word\"\n      },") !=
        std::string::npos);
  CHECK(j.find("\"motors\": [\n      \"A\",\n      \"B\"\n    ],") != std::string::npos);
  CHECK(x.find("<devicenet can_bitrate=\"125000\" motors=\"A B\">") != std::string::npos);
  CHECK(x.find("<value motor=\"A\" command=\"34\" raw=\"1000\" name=\"Get Controller P\" "
               "scaled=\"2.3438\" unit=\"A/mm\" />") != std::string::npos);
  CHECK(x.find("<module>addressed-in</module>") != std::string::npos);
  // Without the section nothing is written for it.
  CHECK(must(write_json(golden_sinrise())).find("devicenet") == std::string::npos);
  CHECK(must(write_xml(golden_sinrise())).find("devicenet") == std::string::npos);
}

TEST_CASE("config: the devicenet fixtures are what the writers produce", "[config][devicenet]") {
  const auto cfg = devicenet_capture();
  for (const char* name : {"devicenet.json", "devicenet.xml"}) {
    INFO(name);
    const auto path = fixture_dir() / name;
    const auto text = must(write_config_text(cfg, *format_from_path(path)));
    if (std::getenv("LMCFG_UPDATE_GOLDEN")) spit(path, text);
    CHECK(slurp(path) == text);
    CHECK(must(read_config_file(path)) == cfg);
  }
}

TEST_CASE("config: devicenet errors in JSON name line, column and pointer", "[config][devicenet]") {
  const std::string ok = "   {\"motor\": \"A\", \"command\": \"34\", \"raw\": 1000}";
  REQUIRE(read_json(json_doc(kHead, ok), "d.json").ok());
  const std::pair<std::string, Expect> cases[] = {
      {json_doc("\"can_bitrate\": 100000, \"motors\": [\"A\"]", ok),
       {Errc::validation_failed,
        "d.json:4:31: /devicenet/can_bitrate: CAN bit rate 100000 is not a DeviceNet rate "
        "(125000, 250000, 500000)"}},
      {json_doc("\"can_bitrate\": \"125000\", \"motors\": [\"A\"]", ok),
       {Errc::parse_error,
        "d.json:4:31: /devicenet/can_bitrate: expected a CAN bit rate (0..4294967295), found "
        "string \"125000\""}},
      {json_doc(kHead, replaced(ok, "\"34\"", "\"35\"")),
       {Errc::validation_failed,
        "d.json:6:30: /devicenet/values/0/command: command ID 35h is a Set command; values are "
        "recorded under their Get command (an even ID)"}},
      {json_doc(kHead, replaced(ok, "\"A\"", "\"B\"")),
       {Errc::validation_failed,
        "d.json:6:14: /devicenet/values/0/motor: motor B is not among the section's motors"}},
      {json_doc(kHead, ok + ",\n" + replaced(ok, "1000", "7")),
       {Errc::validation_failed,
        "d.json:7:30: /devicenet/values/1/command: duplicate command 34h for motor A"}},
      {json_doc(kHead, replaced(ok, "\"34\"", "\"3G\"")),
       {Errc::parse_error,
        "d.json:6:30: /devicenet/values/0/command: expected a command ID as 2 hex digits "
        "(\"34\"), found string \"3G\""}},
      {json_doc(kHead, replaced(ok, "\"34\"", "52")),
       {Errc::parse_error,
        "d.json:6:30: /devicenet/values/0/command: expected a command ID as 2 hex digits "
        "(\"34\"), found 52"}},
      {json_doc(kHead, replaced(ok, "1000", "\"1000\"")),
       {Errc::parse_error,
        "d.json:6:43: /devicenet/values/0/raw: expected a 16-bit word (0..65535), found string "
        "\"1000\""}},
      {json_doc(kHead, replaced(ok, "1000", "65536")),
       {Errc::parse_error,
        "d.json:6:43: /devicenet/values/0/raw: expected a 16-bit word (0..65535), found 65536"}},
      {json_doc(kHead, replaced(ok, "1000", "-1")),
       {Errc::parse_error,
        "d.json:6:43: /devicenet/values/0/raw: expected a 16-bit word (0..65535), found -1"}},
      {json_doc(kHead + ", \"colour\": \"red\"", ok),
       {Errc::parse_error,
        "d.json:4:66: /devicenet/colour: unexpected member; expected one of: can_bitrate, "
        "io_modules, motors, values, live"}},
      {json_doc(kHead, replaced(ok, "\"raw\"", "\"value\"")),
       {Errc::parse_error,
        "d.json:6:45: /devicenet/values/0/value: unexpected member; expected one of: motor, "
        "command, raw, name, scaled, unit"}},
      {json_doc("\"can_bitrate\": 125000, \"motors\": [\"A\", \"E\"]", ok),
       {Errc::parse_error,
        "d.json:4:55: /devicenet/motors/1: expected a motor \"A\"..\"D\", "
        "found string \"E\""}},
      {json_doc("\"can_bitrate\": 125000, \"motors\": [\"A\", \"A\"]", ok),
       {Errc::validation_failed,
        "d.json:4:49: /devicenet/motors: expected motors A..D, each once"}},
      {json_doc(kHead, replaced(ok, "\"A\"", "\"motor A\"")),
       {Errc::parse_error,
        "d.json:6:14: /devicenet/values/0/motor: expected \"controller\" or a motor \"A\"..\"D\", "
        "found string \"motor A\""}},
      {json_doc(kHead, replaced(ok, "\"34\"", "\"80\"")),
       {Errc::validation_failed,
        "d.json:6:30: /devicenet/values/0/command: command ID 80h is outside 00h..7Fh"}},
  };
  for (const auto& [text, expect] : cases) {
    INFO(text);
    check_error(read_json(text, "d.json"), expect);
  }
}

TEST_CASE("config: devicenet errors in XML name the element and attribute", "[config][devicenet]") {
  const std::string ok = "<value motor=\"A\" command=\"34\" raw=\"1000\"/>";
  REQUIRE(read_xml(xml_doc(kAttrs, ok), "d.xml").ok());
  const std::pair<std::string, Expect> cases[] = {
      {xml_doc("can_bitrate=\"100000\" motors=\"A\"", ok),
       {Errc::validation_failed,
        "d.xml: /lmcfg/devicenet/@can_bitrate: CAN bit rate 100000 is not a DeviceNet rate "
        "(125000, 250000, 500000)"}},
      {xml_doc(kAttrs, ok + replaced(ok, "\"34\"", "\"37\"")),
       {Errc::validation_failed,
        "d.xml: /lmcfg/devicenet/values/value[2]/@command: command ID 37h is a Set command; "
        "values are recorded under their Get command (an even ID)"}},
      {xml_doc(kAttrs, replaced(ok, "\"A\"", "\"C\"")),
       {Errc::validation_failed,
        "d.xml: /lmcfg/devicenet/values/value[1]/@motor: motor C is not among the section's "
        "motors"}},
      {xml_doc(kAttrs, ok + ok),
       {Errc::validation_failed,
        "d.xml: /lmcfg/devicenet/values/value[2]/@command: duplicate command 34h for motor A"}},
      {xml_doc(kAttrs, replaced(ok, "\"34\"", "\"x4\"")),
       {Errc::parse_error,
        "d.xml: /lmcfg/devicenet/values/value[1]/@command: expected a command "
        "ID as 2 hex digits (\"34\"), found \"x4\""}},
      {xml_doc(kAttrs, replaced(ok, "1000", "65536")),
       {Errc::parse_error,
        "d.xml: /lmcfg/devicenet/values/value[1]/@raw: expected a 16-bit word "
        "(0..65535 in decimal), found \"65536\""}},
      {xml_doc(kAttrs + " colour=\"red\"", ok),
       {Errc::parse_error,
        "d.xml: /lmcfg/devicenet/@colour: unexpected attribute; expected one "
        "of: can_bitrate, motors"}},
      {xml_doc(kAttrs, ok + "<colour/>"),
       {Errc::parse_error,
        "d.xml: /lmcfg/devicenet/values/colour: unexpected element; expected one of: value"}},
      {xml_doc("can_bitrate=\"125000\" motors=\"A E\"", ok),
       {Errc::parse_error,
        "d.xml: /lmcfg/devicenet/@motors: expected motors A..D separated by "
        "spaces, found \"A E\""}},
  };
  for (const auto& [text, expect] : cases) {
    INFO(text);
    check_error(read_xml(text, "d.xml"), expect);
  }
  // The live values have their own list.
  const std::string live =
      "<lmcfg format=\"lmcfg-drive-config\" format_version=\"3\"><scope layers=\"\" "
      "parameters=\"modified\" curves=\"false\" command_table=\"false\"/><parameters/>"
      "<devicenet can_bitrate=\"125000\" motors=\"\"><live><value motor=\"controller\" "
      "command=\"02\" raw=\"1\"/><value motor=\"B\" command=\"18\" raw=\"1\"/></live>"
      "</devicenet></lmcfg>";
  check_error(read_xml(live, "l.xml"),
              {Errc::validation_failed,
               "l.xml: /lmcfg/devicenet/live/value[2]/@motor: motor B is not among the "
               "section's motors"});
}

TEST_CASE("config: a DeviceNet capture has no layers, curves or command table",
          "[config][devicenet]") {
  auto cfg = devicenet_capture();
  cfg.layer(2).push_back(param(0x13A2, 16));
  cfg.scope.layers[1] = true;
  const auto j = must(write_json(devicenet_capture()));
  auto bad = replaced(j, "\"layers\": [],", "\"layers\": [\n      2\n    ],");
  check_error(read_json(bad, "s.json"),
              {Errc::validation_failed,
               "s.json:27:15: /scope/layers: a DeviceNet capture has no parameter layers, curves "
               "or command table: its scope must name none"});
  CHECK_FALSE(write_json(cfg).ok());
  CHECK_FALSE(write_xml(cfg).ok());
}

TEST_CASE("config: version 2 files read as version 3 files without the devicenet section",
          "[config][devicenet]") {
  for (const char* name : {"golden-sinrise.json", "golden-sinrise.xml"}) {
    INFO(name);
    const auto path = fixture_dir() / name;
    std::string text = slurp(path);
    text = std::string(name).find(".json") != std::string::npos
               ? replaced(text, "\"format_version\": 3", "\"format_version\": 2")
               : replaced(text, "format_version=\"3\"", "format_version=\"2\"");
    CHECK(must(read_config_text(text, name, *format_from_path(path))) == golden_sinrise());
  }
  const auto j = replaced(must(write_json(devicenet_capture())), "\"format_version\": 3",
                          "\"format_version\": 2");
  check_error(read_json(j, "old.json"),
              {Errc::parse_error,
               "old.json:56:16: /devicenet: unexpected member; the devicenet section is new in "
               "format_version 3, this file says 2"});
  const auto x = replaced(must(write_xml(devicenet_capture())), "format_version=\"3\"",
                          "format_version=\"2\"");
  check_error(read_xml(x, "old.xml"),
              {Errc::parse_error,
               "old.xml: /lmcfg/devicenet: unexpected element; the devicenet section is new in "
               "format_version 3, this file says 2"});
  check_error(read_json(replaced(must(write_json(devicenet_capture())), "\"format_version\": 3",
                                 "\"format_version\": 4"),
                        "new.json"),
              {Errc::unsupported_version,
               "new.json: file format_version 4 is newer than this lmcfg supports (3); update "
               "lmcfg"});
}

}  // namespace config_test_config_devicenet
