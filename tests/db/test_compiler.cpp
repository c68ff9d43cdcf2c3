#include <sqlite3.h>

#include <catch2/catch.hpp>
#include <filesystem>
#include <fstream>
#include <sstream>
#include <vector>

#include "db/compiler.hpp"
#include "db_test_support.hpp"

// This file's own namespace: the test binary is a unity build (tests/CMakeLists.txt).
namespace db_test_compiler {

using namespace lmcfg::db;
using lmcfg::db::test::scratch_dir;
using lmcfg::db::test::write_file;

namespace {

const char* kProfiles =
    "profile\tfamily\tsoftware\tversion\tdescription\tsource\n"
    "e1100\tE1100\t\t\t\tentered by hand: test\n";
const char* kParamHeader =
    "upid\tprofiles\tlayer\tname\tpath\ttype\taddress_"
    "usage\tmin\tmax\tdefault\tunit\tscale\tenum\tcomm\tdescription\tsource\n";

// A parameters.tsv row with the given key fields; the others empty.
std::string prow(const std::string& upid, const std::string& profiles, const std::string& layer,
                 const std::string& type, const std::string& source) {
  return upid + "\t" + profiles + "\t" + layer + "\tN\t\t" + type + "\t\t\t\t\t\t\t\t\t\t" +
         source + "\n";
}

std::vector<std::string> messages(const CompileReport& rep) {
  std::vector<std::string> v;
  for (const auto& d : rep.diagnostics) v.push_back(d.str());
  return v;
}

}  // namespace

TEST_CASE("compiler reports malformed parameter rows with file:line:column", "[db]") {
  auto dir = scratch_dir("bad-params");
  write_file(dir / "profiles.tsv", kProfiles);
  write_file(dir / "parameters.tsv",
             std::string("# comment line\n") + kParamHeader +         // lines 1-2
                 prow("13A2", "*", "MC", "UINT16", "seed003 §9.1") +  // 3 ok
                 "13A3\t*\tMC\tB\n" +                                 // 4 column count
                 prow("13G2", "*", "MC", "UINT16", "s") +             // 5 bad hex
                 prow("13A4", "*", "MC", "UINT64", "s") +             // 6 unknown type
                 prow("2008", "*", "MC", "UINT16", "s") +             // 7 layer mismatch
                 prow("13A5", "*", "MC", "UINT16", "") +              // 8 missing source
                 prow("13A2", "e1100", "MC", "UINT16", "s") +         // 9 duplicate
                 prow("0F00", "*", "OS", "UINT16", "s") +             // 10 outside ranges
                 prow("13A6", "e2200", "MC", "UINT16", "s") +         // 11 unknown profile
                 prow("6300", "*", "Other", "UINT16", "s") +          // 12 ok: between ranges
                 prow("13A7", "*", "Other", "UINT16", "s"));          // 13 Other in a range
  auto out = (dir / "out.sqlite").string();
  write_file(out, "previous");
  auto rep = compile_upid_db(dir.string(), out);
  CHECK_FALSE(rep.ok());
  CHECK_FALSE(rep.written);
  const std::string f = (dir / "parameters.tsv").string();
  std::vector<std::string> expected = {
      f + ":4:12: error: expected 16 fields (as in the header, line 2), found 4",
      f + ":5:1: error: bad hex \"13G2\" in column 'upid' (expected 4 hex digits, e.g. 13A2)",
      f + ":6:14: error: unknown type name \"UINT64\" (expected one of: BOOL UINT8 SINT8 UINT16 "
          "SINT16 UINT32 SINT32 "
          "LIN_FLOAT STRING CAP_DIR RADIO_DIR_BIT RADIO_DIR16 ENUM_DIR8 ENUM_DIR16 STRINGLET "
          "CAP_DIRLET)",
      f + ":7:8: error: layer \"MC\" does not match UPID 2008 (in the Intf range 2000-2EFF)",
      f + ":8:30: error: missing source (provenance) in column 'source'",
      f + ":9:1: error: duplicate UPID 13A2 for profile e1100 (first at parameters.tsv:3)",
      f + ":10:8: error: UPID 0F00 is outside every layer range (OS 0000-0EFF, MC 1000-1EFF, Intf "
          "2000-2EFF, Appl 3000-3EFF): its layer must be Other",
      f + ":11:6: error: unknown profile \"e2200\" in column 'profiles' (not in profiles.tsv)",
      f + ":13:8: error: layer \"Other\" does not match UPID 13A7 (in the MC range 1000-1EFF)",
  };
  CHECK(messages(rep) == expected);
  // Nothing written: the previous file is untouched.
  std::ifstream in(out);
  std::stringstream ss;
  ss << in.rdbuf();
  CHECK(ss.str() == "previous");
}

TEST_CASE("compiler reports header, hex and reference errors in the other tables", "[db]") {
  auto dir = scratch_dir("bad-other");
  write_file(dir / "profiles.tsv", "profile\tfamily\tsoftware\tversion\tdescriptoin\tsource\n");
  write_file(dir / "errors.tsv",
             "domain\tcode\tclass\ttext\tdescription\taction\tsource\n"
             "mc\t000C\tErr\tErr: Pos Lag\t\t\ts\n"
             "mc\t00XC\t\tBad\t\t\ts\n"
             "mc\t000c\t\tAgain\t\t\ts\n"
             "mc\t000D\tFatal\tFatal Err: X\t\t\ts\n"
             "mc\t000E\tUser Err\tErr: Y\t\t\ts\n");
  write_file(dir / "motion_commands.tsv",
             "master\tsub\tname\tproducts\tdescription\tsource\n"
             "01\t0\tVAI Go To Pos\t\t\ts\n"
             "1\t0\tShort\t\t\ts\n");
  write_file(
      dir / "motion_command_params.tsv",
      "master\tsub\tindex\toffset\tname\ttype\tunit\tscale\trange\tmin\tmax\tscaled\tsource\n"
      "01\t0\t1\t2\tTarget Position\tSINT32\tmm\t0.0001\t\t\t\t\ts\n"
      "02\t0\t1\t2\tX\tSINT32\t\t\t\t\t\t\ts\n"
      "01\t0\t2\t32\tY\tSINT32\t\t\t\t\t\t\ts\n"
      "01\t0\t3\t6\tZ\tUINT32\tm/s\tfast\t\t\t\t\ts\n"
      "01\t0\t4\t10\tC\tUINT16\t\t\t1..\t\t\t\ts\n"
      "01\t0\t5\t12\tV\tSINT16\tmm\t\t\t\t\t1\ts\n"
      "01\t0\t6\t14\tW\tUINT16\t\t\t1..255\t1\t255\t\ts\n"
      "01\t0\t7\t16\tU\tUINT8\t\t\t1..300\t1\t300\t\ts\n");
  write_file(dir / "notes.tsv", "x\n");
  auto rep = compile_upid_db(dir.string(), "");
  auto p = [&](const char* n) { return (dir / n).string(); };
  std::vector<std::string> expected = {
      p("notes.tsv") + ":1:1: warning: not a table the compiler knows; ignored",
      p("profiles.tsv") +
          ":1:33: error: unknown column \"descriptoin\" in the header (expected: profile family "
          "software version description source)",
      p("profiles.tsv") + ":1:51: error: header lacks column \"description\"",
      p("errors.tsv") +
          ":3:4: error: bad hex \"00XC\" in column 'code' (expected 1 to 8 hex digits, e.g. 000C)",
      p("errors.tsv") +
          ":4:4: error: duplicate error code 000c in domain mc (first at errors.tsv:2)",
      p("errors.tsv") +
          ":5:9: error: unknown error class \"Fatal\" (expected Err, Fatal Err, Cfg Err, Cfg Err "
          "(Fatal), User Err, Setup Err, Runtime Err or empty)",
      p("errors.tsv") +
          ":6:9: error: error class \"User Err\" is not the prefix of the text \"Err: Y\" (seed "
          "001 §10 writes the class before a colon)",
      p("motion_commands.tsv") +
          ":3:1: error: bad hex \"1\" in column 'master' (expected 2 hex digits, e.g. 01)",
      p("motion_command_params.tsv") +
          ":3:1: error: motion command 02/0 is not in motion_commands.tsv",
      p("motion_command_params.tsv") +
          ":4:8: error: bad offset \"32\" (expected the byte offset from the header, 2 or "
          "more, with the value ending by byte 34)",
      p("motion_command_params.tsv") +
          ":5:23: error: bad scale \"fast\" (expected a positive decimal number, e.g. 0.0001)",
      p("motion_command_params.tsv") +
          ":6:22: error: range \"1..\" needs its lower bound in column 'min'",
      p("motion_command_params.tsv") +
          ":7:27: error: a Scaled parameter has no fixed unit (found unit \"mm\")",
      p("motion_command_params.tsv") + ":9:30: error: max 300 is outside the UINT8 range 0..255",
  };
  CHECK(messages(rep) == expected);
}

TEST_CASE("compiler writes a versioned database with provenance atomically", "[db]") {
  auto dir = scratch_dir("good");
  auto out = (dir / "db.sqlite").string();
  auto rep = compile_upid_db(LMCFG_SOURCE_DIR "/tests/fixtures/upid-db", out);
  INFO((rep.diagnostics.empty() ? std::string() : rep.diagnostics.front().str()));
  REQUIRE(rep.ok());
  CHECK(rep.written);
  CHECK(rep.content_hash.rfind("fnv1a64:", 0) == 0);
  CHECK(rep.content_hash.size() == 8 + 16);
  CHECK(rep.counts.at("parameters") == 8);
  // Same sources, same hash; no temp file left behind.
  auto rep2 = compile_upid_db(LMCFG_SOURCE_DIR "/tests/fixtures/upid-db", out);
  CHECK(rep2.content_hash == rep.content_hash);
  for (const auto& e : std::filesystem::directory_iterator(dir))
    CHECK(e.path().filename().string().find(".tmp.") == std::string::npos);

  sqlite3* db = nullptr;
  REQUIRE(sqlite3_open_v2(out.c_str(), &db, SQLITE_OPEN_READONLY, nullptr) == SQLITE_OK);
  auto scalar = [db](const char* sql) {
    sqlite3_stmt* s = nullptr;
    REQUIRE(sqlite3_prepare_v2(db, sql, -1, &s, nullptr) == SQLITE_OK);
    REQUIRE(sqlite3_step(s) == SQLITE_ROW);
    std::string v = reinterpret_cast<const char*>(sqlite3_column_text(s, 0));
    sqlite3_finalize(s);
    return v;
  };
  CHECK(scalar("SELECT value FROM meta WHERE key='schema_version'") ==
        std::to_string(kSchemaVersion));
  CHECK(scalar("SELECT value FROM meta WHERE key='content_hash'") == rep.content_hash);
  // Decoded address usage bits (2136h: 1001h = RAM read + not used for hash).
  CHECK(scalar("SELECT ram_read||ram_write||rom_read||rom_write||no_hash FROM parameters WHERE "
               "upid=0x2136") == "10001");
  CHECK(scalar("SELECT ram_read||ram_write||rom_read||rom_write||no_hash FROM parameters WHERE "
               "upid=0x2008") == "10110");
  CHECK(
      scalar("SELECT count(*) FROM sqlite_master WHERE type='index' AND name='parameters_upid'") ==
      "1");
  CHECK(scalar("SELECT src_file||':'||src_line FROM enum_labels WHERE label='By Parameter'") ==
        "parameters.tsv:7");
  sqlite3_close(db);
}

TEST_CASE("fnv1a64 matches the reference values", "[db]") {
  CHECK(fnv1a64("") == 0xcbf29ce484222325ull);
  CHECK(fnv1a64("a") == 0xaf63dc4c8601ec8cull);
  CHECK(fnv1a64("foobar") == 0x85944171f73967e8ull);
  CHECK(fnv1a64("bar", fnv1a64("foo")) == fnv1a64("foobar"));
}

TEST_CASE("compiler reports malformed seed 000 DeviceNet rows with file:line:column", "[db]") {
  auto dir = scratch_dir("bad-devicenet");
  write_file(dir / "profiles.tsv",
             std::string(kProfiles) + "e100-devicenet\t\tDeviceNet\t\t\tentered by hand: test\n");
  const std::string cmd_header =
      "id\tdirection\tname\ttable_name\trange\tmin\tmax\tunit\tscale\tunit_"
      "text\taddressed\tdirect\tenum\tdescription\tsource\n";
  auto crow = [](const std::string& id, const std::string& direction, const std::string& min,
                 const std::string& max, const std::string& addressed, const std::string& source) {
    return id + "\t" + direction + "\tN\tN\t-\t" + min + "\t" + max + "\t\t\t-\t" + addressed +
           "\t\t\t\t" + source + "\n";
  };
  write_file(dir / "devicenet_commands.tsv",
             cmd_header +                                            // line 1
                 crow("0x11", "set", "", "", "x", "seed000 §5.2") +  // 2 ok
                 crow("0x80", "get", "", "", "x", "s") +             // 3 ID > 7F
                 crow("0x12", "put", "", "", "x", "s") +             // 4 direction
                 crow("0x13", "", "5", "1", "x", "s") +              // 5 max < min
                 crow("0x14", "", "", "", "yes", "s") +              // 6 flag
                 crow("0x11", "set", "", "", "", "s") +              // 7 duplicate
                 crow("0x15", "", "", "", "", ""));                  // 8 source
  write_file(
      dir / "devicenet_parameters.tsv",
      "id\tname\tpath\ttype\tmin\tmax\tdefault\tunit\tscale\tenum\tcomm\tdescription\tsource\n"
      "DeviceNet\\MACID\tMACID\tDeviceNet\\MACID\t\t\t\t\t\t\t\t1\t\tseed000 §3.1\n"
      "DeviceNet\\MACID\tMACID\tDeviceNet\\MACID\t\t\t\t\t\t\t\t\t\ts\n");
  auto rep = compile_upid_db(dir.string(), (dir / "out.sqlite").string());
  CHECK_FALSE(rep.ok());
  const std::string c = (dir / "devicenet_commands.tsv").string();
  const std::string p = (dir / "devicenet_parameters.tsv").string();
  std::vector<std::string> expected = {
      p + ":3:1: error: duplicate DeviceNet parameter \"DeviceNet\\MACID\" (first at "
          "devicenet_parameters.tsv:2)",
      c + ":3:1: error: bad command ID \"0x80\" (expected 0x00..0x7F as Table 5-1 writes it, e.g. "
          "0x1A)",
      c + ":4:6: error: bad direction \"put\" (expected get, set or empty)",
      c + ":5:15: error: max 1 is below min 5",
      c + ":6:19: error: bad value \"yes\" in column 'addressed' (expected x or empty)",
      c + ":7:1: error: duplicate command ID 0x11 (first at devicenet_commands.tsv:2)",
      c + ":8:23: error: missing source (provenance) in column 'source'",
  };
  CHECK(messages(rep) == expected);
}

}  // namespace db_test_compiler
