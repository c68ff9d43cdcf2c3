// Command table entries decoded with the motion command catalogue
// (lib/db/ct_entry.cpp; layout of LinRS §12.1, offsets from MC SW §4.3.143).
#include <catch2/catch.hpp>

#include "common/bytes.hpp"
#include "db/ct_entry.hpp"
#include "db/database.hpp"
#include "db_test_support.hpp"

// This file's own namespace: the test binary is a unity build (tests/CMakeLists.txt).
namespace db_test_ct_entry {

using namespace lmcfg;
using namespace lmcfg::db;
using lmcfg::db::test::fixture_db;
using lmcfg::db::test::seed_ct_entry;

TEST_CASE("decode the seed 003 §12.1 command table entry", "[db]") {
  const auto& db = fixture_db();
  Bytes entry = seed_ct_entry();
  REQUIRE(entry.size() == 64);
  auto r = decode_ct_entry(db, entry);
  REQUIRE(r);
  const CtEntry& e = *r;
  CHECK(e.word0 == 0xA701);
  CHECK(e.link == 0xFFFF);
  CHECK_FALSE(e.has_link());
  CHECK(e.header == 0x0100);
  CHECK(e.command_name == "VAI Go To Pos");
  CHECK(e.name == "Unnamed");
  REQUIRE(e.params.size() == 4);
  CHECK(e.params[0].entry_offset == 6);
  CHECK(e.params[0].raw == 1000000u);
  CHECK(e.params[0].text == "100 mm");
  CHECK(e.params[1].text == "0.5 m/s");
  CHECK(e.raw == entry);
  CHECK(e.summary() ==
        "VAI Go To Pos, target 100 mm, max velocity 0.5 m/s, acceleration 2 m/s2, deceleration 2 "
        "m/s2");

  // Unknown command: not an error, no parameters.
  Bytes unknown = entry;
  unknown[5] = 0x7E;
  auto u = decode_ct_entry(db, unknown);
  REQUIRE(u);
  CHECK(u->command == nullptr);
  CHECK(u->summary() == "unknown motion command 7E00h");

  auto short_entry = decode_ct_entry(db, ByteView(entry).first(40));
  REQUIRE_FALSE(short_entry);
  CHECK(short_entry.error().message == "command table entry has 40 bytes, expected 64");
  CHECK(summary_label("Maximal Velocity") == "max velocity");
  CHECK(summary_label("Position Increment") == "position increment");
}

TEST_CASE("LinRS §12.1 ct entry: the link to the next entry, a 15-character name, raw words",
          "[db][ct_entry]") {
  Bytes entry = seed_ct_entry();
  entry[2] = 0x05;  // link to entry 5
  entry[3] = 0x00;
  const std::string name = "Fifteen chars!!";
  REQUIRE(name.size() == 15);
  std::copy(name.begin(), name.end(), entry.begin() + 38);
  entry[53] = 0x00;
  auto e = decode_ct_entry(fixture_db(), entry);
  REQUIRE(e);
  CHECK(e->word0 == 0xA701);
  CHECK(e->version_note.empty());
  CHECK(e->link == 5);
  CHECK(e->has_link());
  CHECK(e->name == "Fifteen chars!!");
  // A name that fills all 16 bytes of its field stops at the field's end.
  entry[53] = 'X';
  entry[54] = 'Y';
  auto full = decode_ct_entry(fixture_db(), entry);
  REQUIRE(full);
  CHECK(full->name == "Fifteen chars!!X");
  // The unknown command's header is named without its count nibble.
  entry[4] = 0x07;
  entry[5] = 0x7E;
  auto u = decode_ct_entry(fixture_db(), entry);
  REQUIRE(u);
  CHECK(u->command_name == "unknown motion command 7E00h");
  CHECK(u->params.empty());
  auto long_entry = decode_ct_entry(fixture_db(), Bytes(65, 0));
  REQUIRE_FALSE(long_entry);
  CHECK(long_entry.error().code == make_error_code(Errc::invalid_argument));
  CHECK(long_entry.error().message == "command table entry has 65 bytes, expected 64");
}

TEST_CASE("ct entry: summary labels in lower case, maximal/minimal and target shortened",
          "[db][ct_entry]") {
  CHECK(summary_label("Target Position") == "target");
  CHECK(summary_label("Minimal Position") == "min position");
  CHECK(summary_label("Maximal Acceleration") == "max acceleration");
  // Only whole words are shortened.
  CHECK(summary_label("Maximality") == "maximality");
  CHECK(summary_label("Target Positions") == "target positions");
  CtEntry e;
  e.command_name = "Some Command";
  e.params.push_back(CtParam{0, 6, "", 1, "1"});
  e.params.push_back(CtParam{1, 10, "Maximal Velocity", 2, "0.5 m/s"});
  CHECK(e.summary() == "Some Command, parameter 0 1, max velocity 0.5 m/s");
}

TEST_CASE("DCF command table entry version: A701h decodes, another version is said, not misdecoded",
          "[db][ct_entry]") {
  // DCF: offset 0 is the entry version, fixed A701h.
  Bytes entry = seed_ct_entry();
  REQUIRE(get_u16le(entry, 0) == kCtEntryVersion);
  entry[0] = 0x34;
  entry[1] = 0x12;
  auto e = decode_ct_entry(fixture_db(), entry);
  REQUIRE(e);
  CHECK(e->word0 == 0x1234);
  CHECK(e->version_note ==
        "entry version 1234h, expected A701h (DCF): another layout; not decoded, kept raw (a "
        "restore writes its 64 bytes unchanged)");
  CHECK(e->summary() == e->version_note);
  CHECK(e->command == nullptr);
  CHECK(e->params.empty());
  CHECK(e->name.empty());
  CHECK(e->raw == entry);
}

}  // namespace db_test_ct_entry
