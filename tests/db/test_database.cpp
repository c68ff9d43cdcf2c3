#include <sqlite3.h>

#include <atomic>
#include <catch2/catch.hpp>
#include <cstdio>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <map>
#include <thread>
#include <vector>

#include "common/bytes.hpp"
#include "db/ct_entry.hpp"
#include "db/database.hpp"
#include "db_test_support.hpp"
#include "files.hpp"

// This file's own namespace: the test binary is a unity build (tests/CMakeLists.txt).
namespace db_test_database {

using namespace lmcfg;
using namespace lmcfg::db;
using lmcfg::db::test::fixture_db;
using lmcfg::db::test::seed_ct_entry;

namespace {

// Every field of two parameter rows.
bool same_parameter(const Parameter& a, const Parameter& b) {
  auto same_labels = [](const std::vector<EnumLabel>& x, const std::vector<EnumLabel>& y) {
    if (x.size() != y.size()) return false;
    for (std::size_t i = 0; i < x.size(); ++i)
      if (x[i].raw != y[i].raw || x[i].label != y[i].label) return false;
    return true;
  };
  auto au = [](const Parameter& p) { return p.address_usage ? int(p.address_usage->raw) : -1; };
  return a.upid == b.upid && a.profiles == b.profiles && a.layer == b.layer && a.name == b.name &&
         a.path == b.path && a.spec.type == b.spec.type && a.spec.scale == b.spec.scale &&
         a.spec.unit == b.spec.unit && same_labels(a.spec.labels, b.spec.labels) &&
         a.spec.min == b.spec.min && a.spec.max == b.spec.max &&
         a.default_value == b.default_value && au(a) == au(b) && a.comm == b.comm &&
         a.description == b.description && a.prov.source == b.prov.source &&
         a.prov.file == b.prov.file && a.prov.line == b.prov.line;
}

// A synthetic catalogue compiled with the project's compiler: `per_layer` UPIDs
// in each of the four layer ranges, the first `doubled` of each layer with two
// profile rows (t-a, t-b), every seventh row an enum. Row n is named "Row n".
std::string synthetic_db(const std::string& name, int per_layer, int doubled) {
  auto dir = lmcfg::db::test::scratch_dir(name);
  lmcfg::db::test::write_file(dir / "profiles.tsv",
                              "profile\tfamily\tsoftware\tversion\tdescription\tsource\n"
                              "t-a\tE1100\tMC SW\t\tA\tentered by hand: test\n"
                              "t-b\tB1100\tMC SW\t\tB\tentered by hand: test\n");
  std::string t =
      "upid\tprofiles\tlayer\tname\tpath\ttype\taddress_usage\tmin\tmax\tdefault\tunit\tscale\t"
      "enum\tcomm\tdescription\tsource\n";
  const char* layers[] = {"OS", "MC", "Intf", "Appl"};
  int row = 0;
  for (int l = 0; l < 4; ++l)
    for (int i = 0; i < per_layer; ++i) {
      char upid[16];
      std::snprintf(upid, sizeof upid, "%04X", unsigned(l * 0x1000 + i * 3));
      const bool two = i < doubled;
      for (int k = 0; k < (two ? 2 : 1); ++k, ++row) {
        t += std::string(upid) + "\t" + (two ? (k == 0 ? "t-a" : "t-b") : "*") + "\t" + layers[l] +
             "\tRow " + std::to_string(row) + "\t" + layers[l] + "\\Group\\Row " +
             std::to_string(row) + "\t";
        if (row % 7 == 0)
          t += "ENUM_DIR16\t000F\t0\t2\t1\t\t\t0=Off|1=On|2=Auto Row " + std::to_string(row);
        else
          t += "SINT32\t000F\t-" + std::to_string(row) + "\t" + std::to_string(row + 100) + "\t" +
               std::to_string(row % 50) + "\tmm\t0.0001\t";
        t += "\t\tsynthetic\tentered by hand: test\n";
      }
    }
  lmcfg::db::test::write_file(dir / "parameters.tsv", t);
  auto out = (dir / "synthetic.sqlite").string();
  auto rep = compile_upid_db(dir.string(), out);
  if (!rep.ok()) FAIL(rep.diagnostics.front().str());
  return out;
}

// The fixture catalogue compiled into a file of its own (which a test may delete).
std::string fixture_copy(const std::string& name) {
  auto out = (lmcfg::db::test::scratch_dir(name) / "fixture.sqlite").string();
  auto rep = compile_upid_db(LMCFG_SOURCE_DIR "/tests/fixtures/upid-db", out);
  if (!rep.ok()) FAIL(rep.diagnostics.front().str());
  return out;
}
}  // namespace

TEST_CASE("database lookups by UPID, profile, name, layer", "[db]") {
  const auto& db = fixture_db();
  CHECK(db.info().schema_version == kSchemaVersion);
  CHECK(db.info().content_hash.rfind("fnv1a64:", 0) == 0);
  CHECK(db.info().counts.at("parameters") == 8);

  const Parameter* p = db.find(0x13A2);
  REQUIRE(p);
  CHECK(p->name == "P Gain Position Controller Set A");
  CHECK(p->layer == Layer::MC);
  CHECK(p->spec.type == TypeCode::UInt16);
  CHECK(p->default_value == 16);
  CHECK(p->format(16) == "16");
  CHECK(p->prov.source == "entered by hand: test fixture");
  CHECK(p->prov.file == "parameters.tsv");
  CHECK(p->prov.line == 4);
  CHECK(db.find(0x9999) == nullptr);

  // One UPID, two profile groups.
  CHECK(db.find_all(0x1450).size() == 2);
  REQUIRE(db.find(0x1450, "b1100-mc"));
  CHECK(db.find(0x1450, "b1100-mc")->spec.max == 5000000);
  CHECK(db.find(0x1450, "e1100-mc-linrs")->spec.max == 10000000);
  CHECK(db.find(0x1450, "e1100-mc-linrs")->format(1000000) == "100 mm");
  CHECK(db.find(0x13A2, "b1100-mc") != nullptr);  // '*' applies to every profile

  auto gain = db.search("GAIN");
  REQUIRE(gain.size() == 2);
  CHECK(gain[0]->upid == 0x13A2);
  CHECK(gain[1]->upid == 0x2200);
  CHECK(db.search("rs config\\macid").size() == 1);  // tree path substring
  CHECK(db.search("no such thing").empty());

  CHECK(db.in_layer(Layer::Intf).size() == 3);
  CHECK(db.in_layer(Layer::Appl).size() == 1);

  const Parameter* macid = db.find(0x2008);
  REQUIRE(macid);
  CHECK(macid->comm);
  REQUIRE(macid->address_usage);
  CHECK(macid->address_usage->raw == 0x000D);
  CHECK(macid->address_usage->ram_read());
  CHECK_FALSE(macid->address_usage->ram_write());
  CHECK(macid->address_usage->rom_read());
  CHECK(macid->address_usage->rom_write());
  CHECK(macid->format(2) == "By Parameter (2)");
  CHECK(parse_value(macid->spec, "By Hex Switch S1").value() == 0u);
  CHECK(db.find(0x2136)->address_usage->no_hash());
}

TEST_CASE("layer helpers follow seed 003 §10.2", "[db]") {
  CHECK(layer_of_upid(0x0000) == Layer::OS);
  CHECK(layer_of_upid(0x0EFF) == Layer::OS);
  CHECK_FALSE(layer_of_upid(0x0F00));
  CHECK(layer_of_upid(0x13A2) == Layer::MC);
  CHECK(layer_of_upid(0x2008) == Layer::Intf);
  CHECK(layer_of_upid(0x3EFF) == Layer::Appl);
  CHECK_FALSE(layer_of_upid(0x4000));
  CHECK_FALSE(layer_of_upid(0x6300));
  CHECK(layer_base_upid(Layer::Intf) == 0x2000);
  CHECK(layer_from_name("intf") == Layer::Intf);
}

TEST_CASE("errors by domain and code", "[db]") {
  const auto& db = fixture_db();
  const ErrorEntry* e = db.error("linrs", 0xC8);
  REQUIRE(e);
  CHECK(e->text == "Unknown UPID");
  CHECK(e->prov.source == "seed003 §16.1");
  CHECK(db.error("mc", 0x000C) != nullptr);
  CHECK(db.error("MC", 0x000C) != nullptr);
  CHECK(db.error("mc", 0xC8) == nullptr);
  CHECK(db.errors("linrs").size() == 2);
  CHECK(db.errors().size() == 3);
}

TEST_CASE("motion command by header ignores the command count", "[db]") {
  const auto& db = fixture_db();
  CHECK(motion_header(0x01, 0x0, 0x0) == 0x0100);
  CHECK(motion_header(0x01, 0x7, 0x3) == 0x0173);
  const MotionCommand* c = db.motion_command(0x0100);
  REQUIRE(c);
  CHECK(c->name == "VAI Go To Pos");
  CHECK(db.motion_command(0x010F) == c);
  REQUIRE(c->params.size() == 4);
  CHECK(c->params[0].name == "Target Position");
  CHECK(c->params[0].offset == 2);
  CHECK(c->params[3].offset == 14);
  REQUIRE(db.motion_command(0x0171));
  CHECK(db.motion_command(0x0171)->name == "VAI Stop");
  CHECK(db.motion_command(0x0200) == nullptr);
}

TEST_CASE("the real built database: every row has provenance", "[db]") {
  if (!std::filesystem::exists(LMCFG_SOURCE_DIR "/upid-db/parameters.tsv") ||
      !std::filesystem::exists(LMCFG_DB_PATH)) {
    WARN("upid-db/*.tsv or the built database are not there yet: skipped");
    return;
  }
  sqlite3* db = nullptr;
  REQUIRE(sqlite3_open_v2(LMCFG_DB_PATH, &db, SQLITE_OPEN_READONLY, nullptr) == SQLITE_OK);
  for (const char* table :
       {"profiles", "parameters", "enum_labels", "errors", "motion_commands",
        "motion_command_params", "devicenet_parameters", "devicenet_parameter_labels",
        "devicenet_commands", "devicenet_command_labels"}) {
    std::string sql =
        std::string("SELECT count(*) FROM ") + table +
        " WHERE source IS NULL OR trim(source) = '' OR src_file IS NULL OR src_line IS NULL";
    sqlite3_stmt* s = nullptr;
    REQUIRE(sqlite3_prepare_v2(db, sql.c_str(), -1, &s, nullptr) == SQLITE_OK);
    REQUIRE(sqlite3_step(s) == SQLITE_ROW);
    INFO(table);
    CHECK(sqlite3_column_int64(s, 0) == 0);
    sqlite3_finalize(s);
  }
  sqlite3_close(db);

  // The same §12.1 entry against the real catalogue.
  auto real = Database::open(LMCFG_DB_PATH);
  REQUIRE(real);
  CHECK(real->info().counts.at("parameters") > 0);
  auto r = decode_ct_entry(*real, seed_ct_entry());
  REQUIRE(r);
  CHECK(r->command_name == "VAI Go To Pos");
  REQUIRE(r->params.size() == 4);
  CHECK(r->params[0].text == "100 mm");
  CHECK(r->params[1].text == "0.5 m/s");
  // docs/upid-db.md acceptance, through the real catalogue extracted from MC SW §4.3.
  CHECK(r->summary() ==
        "VAI Go To Pos, target 100 mm, max velocity 0.5 m/s, acceleration 2 m/s2, deceleration 2 "
        "m/s2");
}

TEST_CASE("open errors say what and where", "[db]") {
  auto r = Database::open("/nonexistent/lmcfg-upid.sqlite");
  REQUIRE_FALSE(r);
  CHECK(r.error().code == Errc::file_error);
  CHECK(r.error().message.find("/nonexistent/lmcfg-upid.sqlite") != std::string::npos);

  auto dir = lmcfg::db::test::scratch_dir("open");
  auto bogus = (dir / "not-a-db.sqlite").string();
  lmcfg::db::test::write_file(bogus, "this is not sqlite");
  CHECK_FALSE(Database::open(bogus));

  lmcfg::test::set_env("LMCFG_UPID_DB", "/tmp/somewhere/else.sqlite");
  CHECK(Database::default_path().value() == "/tmp/somewhere/else.sqlite");
  lmcfg::test::unset_env("LMCFG_UPID_DB");
  // The lookup without $LMCFG_UPID_DB: tests/tools/test_install.cpp.
}

TEST_CASE("lookups: find returns the rows of the whole table, not copies", "[db]") {
  if (!std::filesystem::exists(LMCFG_DB_PATH)) {
    WARN("the built database is not there yet: skipped");
    return;
  }
  auto opened = Database::open(LMCFG_DB_PATH);
  REQUIRE(opened);
  const Database& db = *opened;

  const Parameter* gain = db.find(0x13A2);
  REQUIRE(gain);
  CHECK(gain->upid == 0x13A2);
  CHECK(gain->name == "P Gain Position Controller Set A");
  CHECK(gain->layer == Layer::MC);
  CHECK(gain->spec.type == TypeCode::UInt16);
  CHECK(gain->spec.min == 0);
  CHECK(gain->spec.max == 65535);
  CHECK(gain->default_value == 15);
  CHECK(gain->profiles == std::vector<std::string>{"e1100-mc-linrs"});
  CHECK(db.find(0x13A2, "e1100-mc-linrs") == gain);
  CHECK(db.find(0x13A2, "b1100-mc") == nullptr);  // no row of that profile

  const Parameter* behavior = db.find(0x121B);  // an enum: 0=No Error|1=Power Off|2=Quick Stop
  REQUIRE(behavior);
  REQUIRE(behavior->spec.labels.size() == 3);
  CHECK(behavior->spec.labels[0].raw == 0);
  CHECK(behavior->spec.labels[0].label == "No Error");
  CHECK(behavior->spec.labels[2].raw == 2);
  CHECK(behavior->spec.labels[2].label == "Quick Stop");
  CHECK(behavior->format(1) == "Power Off (1)");

  // Every row of the whole table, against the per-UPID lookup: one copy of
  // the rows, so find() and find_all() point into parameters().
  const auto& all = db.parameters();
  REQUIRE(all.size() == db.info().counts.at("parameters"));
  std::map<std::uint16_t, std::vector<const Parameter*>> rows;
  for (const auto& p : all) rows[p.upid].push_back(&p);
  for (const auto& [upid, want] : rows) {
    INFO("UPID " << upid);
    auto got = db.find_all(upid);
    REQUIRE(got.size() == want.size());
    for (std::size_t i = 0; i < got.size(); ++i) {
      CHECK(got[i] == want[i]);
      CHECK(same_parameter(*got[i], *want[i]));
    }
    // Without a profile: the first row of the reference profile (E1100), none
    // when only other families name the UPID.
    const Parameter* first_ref = nullptr;
    for (const auto* p : got)
      if (!first_ref && p->applies_to(kReferenceProfile)) first_ref = p;
    CHECK(db.find(upid) == first_ref);
    CHECK(db.find_all(upid) == got);  // the same objects every time
  }
  CHECK(db.find(0x13A2) == gain);
  CHECK_FALSE(db.last_error());
}

TEST_CASE("lookups: two profile rows of one UPID", "[db]") {
  auto opened = Database::open(fixture_copy("two-profiles"));
  REQUIRE(opened);
  const Database& db = *opened;
  auto both = db.find_all(0x1450);
  REQUIRE(both.size() == 2);
  CHECK(both[0]->profiles == std::vector<std::string>{"e1100-mc-linrs"});
  CHECK(both[0]->spec.max == 10000000);
  CHECK(both[1]->profiles == std::vector<std::string>{"b1100-mc"});
  CHECK(both[1]->spec.max == 5000000);
  CHECK(db.find(0x1450) == both[0]);
  CHECK(db.find(0x1450, "b1100-mc") == both[1]);
  CHECK(db.find(0x1450, "e1100-mc-linrs") == both[0]);
  CHECK(db.find(0x1450, "no-such-profile") == nullptr);
  const Parameter* macid = db.find(0x2008);
  REQUIRE(macid);
  REQUIRE(macid->spec.labels.size() == 3);
  CHECK(macid->spec.labels[1].label == "By Hex Switch S1 + Offset");
  CHECK(macid->format(2) == "By Parameter (2)");
}

TEST_CASE("lookups: absent UPIDs stay absent", "[db]") {
  auto opened = Database::open(fixture_copy("absent"));
  REQUIRE(opened);
  const Database& db = *opened;
  for (int round = 0; round < 3; ++round) {
    CHECK(db.find(0x9999) == nullptr);
    CHECK(db.find(0x0F00) == nullptr);
    CHECK(db.find(0x13A3, "b1100-mc") == nullptr);
    CHECK(db.find_all(0x9999).empty());
    CHECK(db.find(0x13A2) != nullptr);
  }
  CHECK(db.parameters().size() == 8);
  CHECK(db.find(0x9999) == nullptr);
  CHECK_FALSE(db.last_error());
}

TEST_CASE("lookups: pointers stay valid after the Database is moved", "[db]") {
  auto opened = Database::open(fixture_copy("move"));
  REQUIRE(opened);
  Database db = std::move(opened).value();
  const Parameter* gain = db.find(0x13A2);
  const Parameter* absent = db.find(0x9999);
  REQUIRE(gain);
  CHECK(absent == nullptr);
  const std::vector<Parameter>* table = &db.parameters();
  const ErrorEntry* c8 = db.error("linrs", 0xC8);
  const MotionCommand* go = db.motion_command(0x0100);
  const Profile* b1100 = db.profile("b1100-mc");
  const DbInfo* info = &db.info();
  auto found = db.search("gain");
  REQUIRE(c8);
  REQUIRE(go);
  REQUIRE(b1100);
  REQUIRE(found.size() == 2);

  Database moved(std::move(db));
  CHECK(moved.find(0x13A2) == gain);
  CHECK(gain->name == "P Gain Position Controller Set A");
  CHECK(moved.find(0x9999) == nullptr);
  CHECK(&moved.parameters() == table);
  CHECK(moved.error("linrs", 0xC8) == c8);
  CHECK(c8->text == "Unknown UPID");
  CHECK(moved.motion_command(0x0100) == go);
  CHECK(go->params.size() == 4);
  CHECK(moved.profile("b1100-mc") == b1100);
  CHECK(&moved.info() == info);
  CHECK(info->counts.at("parameters") == 8);
  CHECK(moved.search("gain") == found);
  CHECK(found[0]->upid == 0x13A2);

  // A moved-from Database behaves as an empty one.
  CHECK(db.find(0x13A2) == nullptr);  // NOLINT(bugprone-use-after-move)
  CHECK(db.parameters().empty());
  CHECK(db.errors().empty());
  CHECK(db.info().counts.empty());
  CHECK(db.is_empty());  // NOLINT(bugprone-use-after-move)
  CHECK_FALSE(moved.is_empty());

  // Move assignment keeps them too; the assigned-over Database's own are gone.
  auto other = Database::open(fixture_copy("move-assign"));
  REQUIRE(other);
  Database target = std::move(other).value();
  CHECK(target.find(0x13A2) != gain);
  target = std::move(moved);
  CHECK(target.find(0x13A2) == gain);
  CHECK(target.error("linrs", 0xC8) == c8);
  CHECK(gain->default_value == 16);
}

TEST_CASE("empty database: every lookup finds nothing", "[db]") {
  // What the tools use when no database file loads: no function takes a
  // nullable Database.
  for (const Database* e : {&Database::empty(), static_cast<const Database*>(nullptr)}) {
    Database local;
    const Database& d = e ? *e : local;
    CHECK(d.is_empty());
    CHECK(d.find(0x13A2) == nullptr);
    CHECK(d.find_all(0x13A2).empty());
    CHECK(d.search("gain").empty());
    CHECK(d.in_layer(Layer::MC).empty());
    CHECK(d.error("linrs", 0xC8) == nullptr);
    CHECK(d.errors().empty());
    CHECK(d.motion_command(0x0100) == nullptr);
    CHECK(d.motion_commands().empty());
    CHECK(d.devicenet_parameters().empty());
    CHECK(d.devicenet_command(0x11) == nullptr);
    CHECK(d.profiles().empty());
    CHECK(d.profile("b1100-mc") == nullptr);
    CHECK(d.parameters().empty());
    CHECK(d.info().content_hash.empty());
  }
  CHECK(&Database::empty() == &Database::empty());
  CHECK_FALSE(fixture_db().is_empty());
}

TEST_CASE("lookups: concurrent use of one const Database", "[db]") {
  constexpr int kPerLayer = 150, kDoubled = 20, kThreads = 8;
  const std::string path = synthetic_db("concurrent", kPerLayer, kDoubled);
  std::vector<std::uint16_t> upids;
  for (int l = 0; l < 4; ++l)
    for (int i = 0; i < kPerLayer; ++i) upids.push_back(std::uint16_t(l * 0x1000 + i * 3));
  for (std::uint16_t u = 0x0F00; u < 0x0F40; ++u) upids.push_back(u);  // absent

  for (int attempt = 0; attempt < 3; ++attempt) {  // several fresh databases
    auto opened = Database::open(path);
    REQUIRE(opened);
    const Database& db = *opened;
    std::atomic<bool> go{false};
    // Per thread: per UPID, find(), find(.., "t-b"), find_all().
    struct Seen {
      const Parameter* any = nullptr;
      const Parameter* b = nullptr;
      std::vector<const Parameter*> all;
    };
    std::vector<std::vector<Seen>> seen(kThreads, std::vector<Seen>(upids.size()));
    std::vector<std::size_t> table_sizes(kThreads), errors_sizes(kThreads), counts(kThreads);
    std::vector<const void*> tables(kThreads);
    std::vector<std::thread> threads;
    for (int t = 0; t < kThreads; ++t)
      threads.emplace_back([&, t] {
        while (!go.load()) std::this_thread::yield();
        const std::size_t n = upids.size();
        for (int round = 0; round < 3; ++round)
          for (std::size_t k = 0; k < n; ++k) {
            // Each thread walks the UPIDs in its own order.
            const std::size_t i = (t % 2 ? n - 1 - k : k) * 7919 % n;
            Seen s{db.find(upids[i]), db.find(upids[i], "t-b"), db.find_all(upids[i])};
            if (round == 0)
              seen[t][i] = s;
            else if (s.any != seen[t][i].any || s.b != seen[t][i].b || s.all != seen[t][i].all)
              seen[t][i].any = reinterpret_cast<const Parameter*>(1);  // flags a change
            if (k == n / 2 && round == 0) {
              tables[t] = &db.parameters();
              table_sizes[t] = db.search("row").size();
              errors_sizes[t] = db.errors().size() + db.motion_commands().size();
              counts[t] = db.info().counts.at("parameters");
            }
          }
      });
    go = true;
    for (auto& th : threads) th.join();

    const std::size_t rows = 4 * (kPerLayer + kDoubled);
    REQUIRE(db.parameters().size() == rows);
    for (int t = 0; t < kThreads; ++t) {
      CHECK(tables[t] == &db.parameters());
      CHECK(table_sizes[t] == rows);
      CHECK(errors_sizes[t] == 0);
      CHECK(counts[t] == rows);
    }
    std::map<std::uint16_t, std::vector<const Parameter*>> want;
    for (const auto& p : db.parameters()) want[p.upid].push_back(&p);
    int mismatches = 0;
    for (std::size_t i = 0; i < upids.size(); ++i) {
      const Seen& first = seen[0][i];
      auto it = want.find(upids[i]);
      if (it == want.end()) {
        mismatches += first.any != nullptr || !first.all.empty();
      } else {
        mismatches += first.all.size() != it->second.size() || first.any != first.all.at(0);
        for (std::size_t k = 0; k < first.all.size() && k < it->second.size(); ++k)
          mismatches += !same_parameter(*first.all[k], *it->second[k]);
        const Parameter* b = nullptr;  // the "*" row or the t-b row
        for (const auto* p : first.all)
          if (!b && p->applies_to("t-b")) b = p;
        mismatches += b == nullptr || first.b != b;
      }
      for (int t = 1; t < kThreads; ++t)
        mismatches +=
            seen[t][i].any != first.any || seen[t][i].b != first.b || seen[t][i].all != first.all;
    }
    CHECK(mismatches == 0);
    CHECK_FALSE(db.last_error());
  }
}

TEST_CASE("open: the file deleted after open", "[db]") {
  // open() read every table: the file is not needed afterwards.
  const std::string path = fixture_copy("deleted");
  auto opened = Database::open(path);
  REQUIRE(opened);
  const Database& db = *opened;
  const Parameter* gain = db.find(0x13A2);
  REQUIRE(gain);
  REQUIRE(std::filesystem::remove(path));
  CHECK(db.find(0x13A2) == gain);
  REQUIRE(db.find(0x2008));
  CHECK(db.find(0x2008)->name == "MACID Source");
  CHECK(db.find(0x9999) == nullptr);
  CHECK(db.parameters().size() == 8);
  REQUIRE(db.error("linrs", 0xC8));
  CHECK(db.motion_command(0x0100)->name == "VAI Go To Pos");
  CHECK(db.info().counts.at("errors") == 3);
  CHECK_FALSE(db.last_error());
  // A new open sees that it is gone.
  auto again = Database::open(path);
  REQUIRE_FALSE(again);
  CHECK(again.error().code == Errc::file_error);
}

TEST_CASE("open: the file overwritten in place after open", "[db]") {
  // Nothing in lmcfg writes the file in place (the compiler replaces it by
  // rename). open() read every table, so an open Database serves what it read;
  // a new open() of the damaged file fails and names it.
  const std::string path = fixture_copy("corrupted");
  std::string original;
  {
    std::ifstream in(path, std::ios::binary);
    original.assign(std::istreambuf_iterator<char>(in), {});
  }
  REQUIRE(original.size() > 4096);
  auto overwrite = [&](const std::string& bytes) {
    std::fstream f(path,
                   std::ios::binary | std::ios::in | std::ios::out);  // same inode, no truncation
    f.write(bytes.data(), static_cast<std::streamsize>(bytes.size()));
  };

  auto opened = Database::open(path);
  REQUIRE(opened);
  const Database& db = *opened;
  const Parameter* gain = db.find(0x13A2);
  REQUIRE(gain);

  overwrite(std::string(original.size(), '\xA5'));
  CHECK(db.find(0x13A2) == gain);
  CHECK(gain->name == "P Gain Position Controller Set A");
  const ErrorEntry* c8 = db.error("linrs", 0xC8);
  REQUIRE(c8);
  CHECK(c8->text == "Unknown UPID");
  REQUIRE(db.motion_command(0x0100));
  CHECK(db.motion_command(0x0100)->params.size() == 4);
  CHECK(db.info().counts.at("parameters") == 8);
  CHECK_FALSE(db.last_error());

  auto again = Database::open(path);
  REQUIRE_FALSE(again);
  CHECK(again.error().message.find(path) != std::string::npos);
  CAPTURE(again.error().message);

  overwrite(original);
  auto whole = Database::open(path);
  REQUIRE(whole);
  CHECK(whole->find(0x13A2)->name == "P Gain Position Controller Set A");
}

TEST_CASE("open: a table that cannot be read fails the open and names it", "[db]") {
  // Every table is read by open(): a damaged one is an open error, not a
  // missing row later.
  const std::string path = fixture_copy("broken-table");
  sqlite3* raw = nullptr;
  REQUIRE(sqlite3_open_v2(path.c_str(), &raw, SQLITE_OPEN_READWRITE, nullptr) == SQLITE_OK);
  REQUIRE(sqlite3_exec(raw, "DROP TABLE motion_command_params", nullptr, nullptr, nullptr) ==
          SQLITE_OK);
  sqlite3_close(raw);
  auto r = Database::open(path);
  REQUIRE_FALSE(r);
  CHECK(r.error().code == Errc::parse_error);
  CHECK(r.error().message.rfind("UPID database " + path + ": motion_command_params: ", 0) == 0);
  CAPTURE(r.error().message);
}

TEST_CASE("open: a path with URI characters, a relative path", "[db]") {
  // open() hands SQLite a file: URI; the path must arrive unchanged.
  const std::string src = fixture_copy("uri-chars");
#ifdef _WIN32
  const char* odd_name = "odd %41 x=1 #frag";  // '?' cannot be in a Windows file name
#else
  const char* odd_name = "odd %41 ?x=1 #frag";
#endif
  auto dir = std::filesystem::path(src).parent_path() / odd_name;
  std::filesystem::create_directories(dir);
  const auto odd = dir / "fixture.sqlite";
  std::filesystem::copy_file(src, odd);
  std::filesystem::remove(src);  // a wrong decoding would find nothing
  auto r = Database::open(odd.string());
  REQUIRE(r);
  CHECK(r->info().path == odd.string());
  REQUIRE(r->find(0x13A2));
  CHECK(r->find(0x13A2)->name == "P Gain Position Controller Set A");

  std::error_code ec;
  auto rel = std::filesystem::relative(odd, ec);
  if (ec || rel.empty() || rel.is_absolute()) return;
  auto rr = Database::open(rel.string());
  REQUIRE(rr);
  CHECK(rr->info().path == rel.string());
  CHECK(rr->find(0x2008) != nullptr);
}

}  // namespace db_test_database
