#include <catch2/catch.hpp>
#include <regex>

#include "common/layers.hpp"
#include "config/model.hpp"
#include "test_config_support.hpp"

// This file's own namespace: the test binary is a unity build (tests/CMakeLists.txt).
namespace config_test_model {

using namespace lmcfg;
using namespace lmcfg::config;
using namespace lmcfg::config::testing;

namespace {
// Collects the 4 data bytes of every "Rx: 01 11 0A 02 <sub> 00 <state> <id> 00 b b b b 04" line
// of seed 003 between two markers.
Bytes transcript_block(const std::string& seed, const std::string& from, const std::string& to,
                       const std::string& sub) {
  auto a = seed.find(from);
  auto b = seed.find(to, a);
  REQUIRE(a != std::string::npos);
  REQUIRE(b != std::string::npos);
  std::string part = seed.substr(a, b - a);
  std::regex rx("Rx: 01 11 0A 02 " + sub +
                " 00 \\**([0-9A-F]{2})\\** [0-9A-F]{2} 00 ([0-9A-F]{2} [0-9A-F]{2} [0-9A-F]{2} "
                "[0-9A-F]{2}) 04");
  Bytes out;
  for (std::sregex_iterator it(part.begin(), part.end(), rx), end; it != end; ++it) {
    auto bytes = from_hex((*it)[2].str());
    out.insert(out.end(), bytes->begin(), bytes->end());
  }
  return out;
}
}  // namespace

TEST_CASE("config: fixture curve and CT bytes agree with the seed 003 transcripts", "[config]") {
  const auto seed = slurp(std::filesystem::path(LMCFG_SEEDS_DIR) / "003_10816135b563b7c9.txt");
  if (seed.empty()) {
    WARN("seed 003 not found at " LMCFG_SEEDS_DIR "; skipping the transcript cross-check");
    return;
  }
  // §11.1: 18 telegrams of 4 bytes = 72 bytes; the info block is the first 70 (2 padding bytes).
  Bytes info =
      transcript_block(seed, "Reading Curve 1 Info Block Data", "Reading Curve data", "40");
  REQUIRE(info.size() == 72);
  info.resize(70);
  CHECK(info == sinrise_info());
  // Data: setpoint 1's line lost a byte (a transcription erratum), so the regex finds 20 of 21.
  Bytes data =
      transcript_block(seed, "Reading Curve data 21 Position values", "11.2 Write Curve", "40");
  REQUIRE(data.size() == 80);
  const Bytes all = sinrise_data();
  CHECK(Bytes(all.begin() + 4, all.end()) == data);
  // §12.1: 16 telegrams of 4 bytes = the 64-byte entry.
  Bytes ct =
      transcript_block(seed, "12.1 Read Command Table Entry", "12.2 Write Command Table", "86");
  CHECK(ct == ct_entry2());
}

TEST_CASE("config: SinRise decodes", "[config]") {
  const Curve c{1, sinrise_info(), sinrise_data()};
  REQUIRE(c.info.size() == 70);
  REQUIRE(c.data.size() == 84);
  auto v = decode_curve(c);
  REQUIRE(v.ok());
  CHECK(v->name == "SinRise");
  CHECK(v->info_size == 70);
  CHECK(v->object_type == 0x0003);
  CHECK(CurveView::x_name(v->x_code) == "time");
  CHECK(CurveView::y_name(v->y_code) == "position");
  CHECK(v->setpoint_count == 21);
  CHECK(v->bytes_per_setpoint == 4);
  CHECK(v->curve_id == 1);
  CHECK(v->length == 100000);
  CHECK(v->length_ms_text() == "1000");
  CHECK(v->x_dimension == 0x1A);
  CHECK(v->y_dimension == 5);
  CHECK(v->wizard == 0x0301);
  CHECK(v->wizard_params[0] == 100000);
  CHECK(v->wizard_params[2] == 1000000);
  REQUIRE(v->setpoints.size() == 21);
  CHECK(v->setpoints.front() == 0);
  CHECK(v->setpoints[1] == 6156);
  CHECK(v->setpoints.back() == 1000000);
  for (std::size_t i = 1; i < v->setpoints.size(); ++i)
    CHECK(v->setpoints[i] > v->setpoints[i - 1]);
}

TEST_CASE("config: a curve name byte that is not printable ASCII decodes as an escape",
          "[config]") {
  // A drive may hold any byte in the name field (info off 8, char[22]); the
  // decoded view is UTF-8 text in both file formats.
  Curve c{1, sinrise_info(), sinrise_data()};
  c.info[8 + 6] = 0x89;  // "SinRis\x89"
  c.info[8 + 7] = '\\';
  c.info[8 + 8] = 0x01;
  auto v = decode_curve(c);
  REQUIRE(v.ok());
  CHECK(v->name == "SinRis\\x89\\x5C\\x01");
}

TEST_CASE("config: curve length text is exact", "[config]") {
  CurveView v;
  v.length = 12345;
  CHECK(v.length_ms_text() == "123.45");
  v.length = 12340;
  CHECK(v.length_ms_text() == "123.4");
  v.length = 5;
  CHECK(v.length_ms_text() == "0.05");
}

TEST_CASE("config: curve block size checks", "[config]") {
  Curve c{1, sinrise_info(), sinrise_data()};
  CHECK(check_curve_blocks(c).ok());
  c.data.pop_back();
  auto r = check_curve_blocks(c);
  REQUIRE_FALSE(r.ok());
  CHECK(r.error().code == make_error_code(Errc::validation_failed));
  CHECK(r.error().message ==
        "data block has 83 bytes but the info block says 21 setpoints x 4 bytes = 84");
  c.data = sinrise_data();
  c.info.push_back(0);
  CHECK(check_curve_blocks(c).error().message ==
        "info block has 71 bytes but its header (offset 0) says 70");
  c.info = hex("08 00");
  CHECK(check_curve_blocks(c).error().message ==
        "info block has 2 bytes; expected at least 8 (sizes at offsets 0, 4 and 6)");
  Curve tiny{9, hex("08 00 03 00 02 00 04 00"), hex("01 00 00 00 FF FF FF FF")};
  CHECK(check_curve_blocks(tiny).ok());
  CHECK_FALSE(decode_curve(tiny).ok());
}

TEST_CASE("config: CT entry name and layers", "[config]") {
  CHECK(ct_entry_name(ct_entry2()) == "Unnamed");
  CHECK(ct_entry_name(hex("01 02")) == "");
  CHECK(lmcfg::layers::of_upid(0x0000) == 1);
  CHECK(lmcfg::layers::of_upid(0x0EFF) == 1);
  CHECK(lmcfg::layers::of_upid(0x0F00) == 0);
  CHECK(lmcfg::layers::of_upid(0x13A2) == 2);
  CHECK(lmcfg::layers::of_upid(0x2076) == 3);
  CHECK(lmcfg::layers::of_upid(0x3EFF) == 4);
  CHECK(lmcfg::layers::of_upid(0x3F00) == 0);
  CHECK(lmcfg::layers::name(3) == "Intf");
}

TEST_CASE("config: model validation finds problems", "[config]") {
  CHECK(validate(golden_sinrise()).ok());
  CHECK(validate(everything()).ok());
  {
    auto c = golden_sinrise();
    c.layer(3).push_back(param(0x2012, 1));
    auto is = find_issue(c);
    REQUIRE(is);
    CHECK(is->where == Issue::Where::param);
    CHECK(is->layer == 3);
    CHECK(is->index == 4);
    CHECK(is->message == "duplicate UPID 2012h in layer 3 (Intf)");
    CHECK(validate(c).error().message ==
          "invalid configuration: layer 3 parameter #5: duplicate UPID 2012h in layer 3 (Intf)");
  }
  {
    auto c = golden_sinrise();
    c.layer(2).push_back(param(0x2000, 1));
    CHECK(find_issue(c)->message == "UPID 2000h is outside layer 2 (MC) range 1000-1EFF");
  }
  {
    auto c = golden_sinrise();
    c.ct_entries.push_back(CtEntry{256, hex("00")});
    CHECK(find_issue(c)->message == "command table entry ID 256 is outside 0..255");
  }
  {
    auto c = golden_sinrise();
    c.curves.push_back(c.curves[0]);
    CHECK(find_issue(c)->message == "duplicate curve ID 1");
  }
  {
    auto c = golden_sinrise();
    c.scope.layers[2] = false;
    CHECK(find_issue(c)->message ==
          "layer 3 (Intf) has parameters but is not in the scope's layers");
  }
  {
    auto c = golden_sinrise();
    c.scope.curves = false;
    CHECK(find_issue(c)->field == "curves");
  }
  {
    auto c = golden_sinrise();
    c.scope.drive_lacks = {"curves"};  // but the scope says curves were captured
    CHECK(find_issue(c)->message == "the drive lacks 'curves', but the scope says it was captured");
    c.curves.clear();
    c.scope.curves = false;
    CHECK_FALSE(find_issue(c));
    c.scope.drive_lacks = {"curves", "curves"};
    CHECK(find_issue(c)->message == "'curves' is listed twice");
    c.scope.drive_lacks = {"parameters"};
    CHECK(find_issue(c)->message ==
          "'parameters' is not a group (expected curves or command_table)");
    CHECK(find_issue(c)->field == "drive_lacks");
  }
  {
    auto c = golden_sinrise();
    c.identity.labels["bad"] = "line\nbreak";
    auto is = find_issue(c);
    REQUIRE(is);
    CHECK(is->field == "labels.bad");
    c.identity.labels["bad"] = "\xC3";  // truncated UTF-8
    CHECK(find_issue(c));
    c.identity.labels["bad"] = "\xC3\xBC";
    CHECK_FALSE(find_issue(c));
  }
}

TEST_CASE("config: canonical order", "[config]") {
  auto c = golden_sinrise();
  std::swap(c.layer(3)[0], c.layer(3)[3]);
  c.curves.insert(c.curves.begin(), Curve{5, sinrise_info(), sinrise_data()});
  canonicalize(c);
  CHECK(c.layer(3)[0].upid == 0x200E);
  CHECK(c.layer(3)[3].upid == 0x2076);
  CHECK(c.curves[0].id == 1);
  CHECK(c.find_param(0x206C)->value == 3);
  CHECK(c.find_param(0x206D) == nullptr);
  CHECK(c.find_curve(5) != nullptr);
  CHECK(c.find_ct_entry(2) != nullptr);
}

}  // namespace config_test_model
