// config/json_writer.hpp: for the same calls, JsonTextWriter writes the text
// that nlohmann's dump(indent, ' ', false, replace) writes of what JsonBuilder
// builds; nlohmann's own dump is the reference here, not the code under test.
#include <catch2/catch.hpp>
#include <functional>
#include <random>

#include "config/json_writer.hpp"

// This file's own namespace: the test binary is a unity build (tests/CMakeLists.txt).
namespace config_test_json_writer {

using lmcfg::config::JsonBuilder;
using lmcfg::config::JsonTextWriter;
using OJson = nlohmann::ordered_json;

// The same calls on both writers: (text written, text of the built dump).
template <class F>
std::pair<std::string, std::string> both(F&& calls, int indent = 2) {
  std::string text;
  JsonTextWriter t(text, indent);
  calls(t);
  JsonBuilder b;
  calls(b);
  return {text, b.take().dump(indent, ' ', false, OJson::error_handler_t::replace)};
}

TEST_CASE("json writer: objects, arrays, empty ones and scalars as dump(2) writes them",
          "[config][json_writer]") {
  auto [text, dumped] = both([](auto& w) {
    w.begin_object();
    w.key("name");
    w.value("line1/axis1");
    w.key("id");
    w.value(17);
    w.key("negative");
    w.value(std::int64_t{-5});
    w.key("big");
    w.value(std::uint64_t{18446744073709551615ULL});
    w.key("ok");
    w.value(true);
    w.key("no");
    w.value(false);
    w.key("none");
    w.value(nullptr);
    w.key("empty_object");
    w.begin_object();
    w.end_object();
    w.key("empty_array");
    w.begin_array();
    w.end_array();
    w.key("list");
    w.begin_array();
    w.value("a");
    w.begin_object();
    w.key("x");
    w.begin_array();
    w.value(1);
    w.value(2);
    w.end_array();
    w.end_object();
    w.begin_array();
    w.end_array();
    w.value(nullptr);
    w.end_array();
    w.end_object();
  });
  CHECK(text == dumped);
  CHECK(text.substr(0, 27) == "{\n  \"name\": \"line1/axis1\",\n");
}

TEST_CASE("json writer: a built value inside, at any depth, as dump writes it",
          "[config][json_writer]") {
  const OJson kept = OJson::parse(R"([{"upid":"13A2","why":"kept"},[],{},"x",[1,[2,{"y":null}]]])");
  for (int indent : {0, 2, 4}) {
    auto [text, dumped] = both(
        [&](auto& w) {
          w.begin_array();
          w.value(kept);
          w.begin_object();
          w.key("kept");
          w.value(kept);
          w.key("empty");
          w.value(OJson::array());
          w.key("scalar");
          w.value(OJson(3));
          w.end_object();
          w.end_array();
        },
        indent);
    CHECK(text == dumped);
  }
}

TEST_CASE("json writer: strings escaped as dump escapes them, bad UTF-8 replaced",
          "[config][json_writer]") {
  const std::vector<std::string> strings = {
      "",
      "plain text",
      "quote \" and backslash \\",
      "tab\tnewline\ncarriage\rbell\x07 nul" + std::string(1, '\0') + "end",
      "del \x7f",
      "UTF-8 \xc3\xa4\xe2\x82\xac \xf0\x9f\x98\x80",
      "bad \xff\xfe middle",
      "cut \xe2\x82",
      "overlong \xc0\xaf",
  };
  for (const auto& s : strings) {
    auto [text, dumped] = both([&](auto& w) {
      w.begin_object();
      w.key(s);
      w.value(s);
      w.end_object();
    });
    CHECK(text == dumped);
  }
}

TEST_CASE("json writer: random strings and shapes agree with dump", "[config][json_writer]") {
  std::mt19937 rng(20261129);
  auto random_string = [](std::mt19937& r) {
    std::string s(r() % 12, ' ');
    for (char& c : s) c = static_cast<char>(r() % 256);
    return s;
  };
  for (int round = 0; round < 200; ++round) {
    const unsigned seed = static_cast<unsigned>(rng());
    auto calls = [&](auto& w) {
      std::mt19937 r(seed);  // the same shape for both writers
      std::function<void(int)> any = [&](int depth) {
        switch (depth > 3 ? r() % 3 : r() % 5) {
          case 0:
            w.value(random_string(r));
            break;
          case 1:
            w.value(static_cast<std::int64_t>(r()) - std::int64_t{2147483648});
            break;
          case 2:
            w.value(nullptr);
            break;
          case 3: {
            w.begin_array();
            for (unsigned i = r() % 4; i > 0; --i) any(depth + 1);
            w.end_array();
            break;
          }
          default: {
            w.begin_object();
            for (unsigned i = r() % 4; i > 0; --i) {
              w.key("k" + std::to_string(i));
              any(depth + 1);
            }
            w.end_object();
          }
        }
      };
      any(0);
    };
    auto [text, dumped] = both(calls);
    INFO("round " << round);
    CHECK(text == dumped);
  }
}

}  // namespace config_test_json_writer
