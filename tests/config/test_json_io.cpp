// The JSON reader and writer (json_io.cpp, json_write.cpp, json_fields.cpp,
// json_read_v1.cpp): the document's frame and each kind of field, with the
// exact located messages.
#include <catch2/catch.hpp>
#include <functional>
#include <nlohmann/json.hpp>

#include "config/json_io.hpp"
#include "test_config_support.hpp"

// This file's own namespace: the test binary is a unity build (tests/CMakeLists.txt).
namespace config_test_json_io {

using namespace lmcfg;
using namespace lmcfg::config;
using namespace lmcfg::config::testing;

namespace {

using ojson = nlohmann::ordered_json;

// A small valid document on one line, so that a message's column is easy to
// check by eye; `edit` changes it first.
std::string doc(const std::function<void(ojson&)>& edit = {}) {
  ojson d = ojson::parse(R"({"format":"lmcfg-drive-config","format_version":3,
    "scope":{"layers":[2],"parameters":"modified","curves":true,"command_table":true},
    "parameters":[{"layer":2,"params":[{"upid":"13A2","value":16}]}]})");
  if (edit) edit(d);
  return d.dump();
}

std::string message(const std::string& text) {
  auto r = read_json(text, "t.json");
  REQUIRE_FALSE(r.ok());
  return r.error().message;
}

}  // namespace

TEST_CASE("config: text positions", "[config]") {
  CHECK(text_position("ab\ncd", 0).line == 1);
  CHECK(text_position("ab\ncd", 4).line == 2);
  CHECK(text_position("ab\ncd", 4).column == 2);
  CHECK(text_position("ab", 99).column == 3);
}

TEST_CASE("json_io: a small document reads, and writes every layer and member", "[config][json]") {
  const auto cfg = must(read_json(doc(), "t.json"));
  REQUIRE(cfg.layer(2).size() == 1);
  CHECK(cfg.layer(2)[0].value == 16);
  CHECK(cfg.scope.layers == std::array<bool, 4>{false, true, false, false});
  const auto text = must(write_json(cfg));
  CHECK(
      text.find("\"identity\": {\n    \"macid\": \"\",\n    \"link\": {\n      \"port\": \"\",") !=
      std::string::npos);
  CHECK(text.find("\"upid_db\": {\n      \"version\": \"\",\n      \"hash\": \"\"\n    },") !=
        std::string::npos);
  CHECK(text.find("\"layer\": 4,\n      \"name\": \"Appl\",\n      \"params\": []") !=
        std::string::npos);
  CHECK(text.find("\"curves\": [],\n  \"command_table\": []\n}\n") != std::string::npos);
  CHECK(text.find("devicenet") == std::string::npos);
}

TEST_CASE("json_io: a long string in a message is cut at a character boundary", "[config][json]") {
  // 39 ASCII bytes and a two-byte character across the 40-byte cut.
  const std::string name = std::string(39, 'a') + "\xC3\xA4" + "bbb";
  CHECK(message(doc([&](ojson& d) { d["parameters"][0]["params"][0]["upid"] = name; })) ==
        "t.json:1:176: /parameters/0/params/0/upid: expected a UPID as 4 hex digits (\"13A2\"), "
        "found string \"" +
            std::string(39, 'a') + "...\"");
}

TEST_CASE("json_io: each kind of field says what it expected, and where", "[config][json]") {
  CHECK(message(doc([](ojson& d) { d["parameters"][0]["params"][0]["upid"] = "13G2"; })) ==
        "t.json:1:176: /parameters/0/params/0/upid: expected a UPID as 4 hex digits (\"13A2\"), "
        "found string \"13G2\"");
  CHECK(message(doc([](ojson& d) { d["parameters"][0]["params"][0]["type"] = 16; })) ==
        "t.json:1:201: /parameters/0/params/0/type: expected a type code (0..15), found 16");
  CHECK(message(doc([](ojson& d) {
          d["scope"]["layers"] = {2, 2};
        })) == "t.json:1:72: /scope/layers/1: layer 2 listed twice");
  CHECK(message(doc([](ojson& d) { d["scope"]["layers"] = {5}; })) ==
        "t.json:1:70: /scope/layers/0: expected a layer number 1..4, found 5");
  CHECK(message(doc([](ojson& d) { d["scope"]["parameters"] = "all"; })) ==
        "t.json:1:86: /scope/parameters: expected \"modified\" or \"full\", found string \"all\"");
  CHECK(message(doc([](ojson& d) { d["scope"]["curves"] = 1; })) ==
        "t.json:1:106: /scope/curves: expected true or false, found 1");
  CHECK(message(doc([](ojson& d) {
          d["identity"]["labels"] = {{"axis", 1}};
        })) == "t.json:1:227: /identity/labels/axis: expected a string, found 1");
  CHECK(message(doc([](ojson& d) { d["identity"]["link"] = "COM1"; })) ==
        "t.json:1:217: /identity/link: expected an object, found string \"COM1\"");
  CHECK(message(doc([](ojson& d) {
          d["identity"]["upid_db"] = {{"sha", ""}};
        })) ==
        "t.json:1:227: /identity/upid_db/sha: unexpected member; expected one of: version, hash");
  CHECK(message(doc([](ojson& d) {
          d["curves"] = {{{"id", 1}, {"info", {"46 00"}}}};
        })) == "t.json:1:208: /curves/0: missing member \"data\"");
  CHECK(message(doc([](ojson& d) {
          d["command_table"] = {{{"id", 1}, {"raw", {"01"}}, {"decoded", "x"}}};
        })) == "t.json:1:246: /command_table/0/decoded: expected an object, found string \"x\"");
}

TEST_CASE("json_io: the devicenet section's kinds, and its format version", "[config][json]") {
  const auto dn = [](const std::function<void(ojson&)>& edit) {
    return doc([&](ojson& d) {
      d["scope"] = {{"layers", ojson::array()},
                    {"parameters", "modified"},
                    {"curves", false},
                    {"command_table", false}};
      d["parameters"] = ojson::array();
      d["devicenet"] = {{"can_bitrate", 125000},
                        {"motors", {"A"}},
                        {"values", {{{"motor", "A"}, {"command", "34"}, {"raw", 1}}}}};
      edit(d);
    });
  };
  CHECK(must(read_json(dn([](ojson&) {}), "t.json")).devicenet->values.at(0).command == 0x34);
  CHECK(message(dn([](ojson& d) { d["devicenet"]["motors"] = {"E"}; })) ==
        "t.json:1:194: /devicenet/motors/0: expected a motor \"A\"..\"D\", found string \"E\"");
  CHECK(message(dn([](ojson& d) { d["devicenet"]["values"][0]["motor"] = 0; })) ==
        "t.json:1:218: /devicenet/values/0/motor: expected \"controller\" or a motor \"A\"..\"D\", "
        "found 0");
  CHECK(message(dn([](ojson& d) { d["devicenet"]["values"][0]["command"] = "134"; })) ==
        "t.json:1:232: /devicenet/values/0/command: expected a command ID as 2 hex digits "
        "(\"34\"), found string \"134\"");
  CHECK(message(dn([](ojson& d) { d["devicenet"]["io_modules"] = {7}; })) ==
        "t.json:1:261: /devicenet/io_modules/0: expected a string, found 7");
  CHECK(message(dn([](ojson& d) { d["format_version"] = 2; })) ==
        "t.json:1:162: /devicenet: unexpected member; the devicenet section is new in "
        "format_version 3, this file says 2");
}

}  // namespace config_test_json_io
