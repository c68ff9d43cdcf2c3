// lmcfg db scan (docs/upid-db.md): learn a firmware profile from a (simulated) drive.
#include <unistd.h>

#include <catch2/catch.hpp>
#include <filesystem>
#include <fstream>
#include <sstream>

#include "db/compiler.hpp"
#include "db/database.hpp"
#include "db/value.hpp"
#include "e2e_support.hpp"
#include "files.hpp"
#include "ops/db_scan.hpp"

// This file's own namespace: the test binary is a unity build (tests/CMakeLists.txt).
namespace ops_test_db_scan {

namespace fs = std::filesystem;
using namespace lmcfg;
using test::slurp;

namespace {

constexpr const char* kFixture = "commissioned-axis.json";
constexpr const char* kProfile = "e1100-fw-scantest";

fs::path scan_scratch(const std::string& name) {
  auto d = fs::temp_directory_path() / ("lmcfg-scantest-" + std::to_string(::getpid())) / name;
  fs::remove_all(d);
  fs::create_directories(d);
  return d;
}

const db::Database& real_db() {
  static const std::optional<db::Database> d = test::built_database();
  if (!d) throw std::runtime_error("the built UPID database (" LMCFG_DB_PATH ") does not open");
  return *d;
}

ops::DbScanOptions scan_options(ops::ScanStore* store = nullptr) {
  ops::DbScanOptions o;
  o.profile.id = kProfile;
  o.date = "2026-01-02";
  o.names_from = "e1100-mc-linrs";
  o.store = store;
  return o;
}

std::int64_t decoded(std::uint16_t type, std::uint32_t raw) {
  auto t = db::type_from_code(type);
  REQUIRE(t);
  return db::decode_value(*t, raw).integer;
}

}  // namespace

TEST_CASE("db scan: the scanned profile is the simulated drive's own parameter set", "[db][scan]") {
  test::SimRig rig(kFixture);
  const auto& d = real_db();
  std::vector<std::pair<std::string, std::size_t>> phases;
  auto opt = scan_options();
  opt.progress = [&](const std::string& phase, std::size_t done, std::size_t total) {
    if (phases.empty() || phases.back().first != phase) phases.emplace_back(phase, total);
    (void)done;
  };
  auto r = ops::scan_drive_profile(*rig.client, d, opt);
  REQUIRE(r.ok());
  const auto& params = rig.drive->state().params;
  REQUIRE(r->rows.size() == params.size());
  CHECK(r->asked == params.size());
  CHECK(r->resumed == 0);
  CHECK(r->refused == 0);
  CHECK(r->source == "scanned from a drive: e1100-fw-scantest 2026-01-02 MACID 11h");
  CHECK(r->profile.family == "E1100");  // from --names-from
  std::size_t known = 0, unknown = 0;
  for (const auto& row : r->rows) {
    INFO("UPID " << std::hex << row.scanned.upid);
    auto it = params.find(row.scanned.upid);
    REQUIRE(it != params.end());
    const auto& p = it->second;
    CHECK(row.scanned.type == p.type);
    CHECK(row.scanned.address_usage == p.address_usage);
    CHECK(row.scanned.limits.min == std::optional<std::uint32_t>(p.min));
    CHECK(row.scanned.limits.max == std::optional<std::uint32_t>(p.max));
    CHECK(row.scanned.limits.def == std::optional<std::uint32_t>(p.def));
    // Names merged from the database where it knows the UPID; empty otherwise.
    if (const auto* k = d.find(row.scanned.upid, "e1100-mc-linrs")) {
      ++known;
      CHECK(row.known);
      CHECK(row.name == k->name);
      CHECK(row.path == k->path);
      CHECK(row.unit == k->spec.unit);
      CHECK(row.scale == k->spec.scale);
      CHECK(row.comm == k->comm);
      CHECK(row.labels.size() == k->spec.labels.size());
    } else {
      ++unknown;
      CHECK_FALSE(row.known);
      CHECK(row.name.empty());
    }
  }
  CHECK(known == r->named);
  CHECK(known > 0);
  CHECK(unknown > 0);
  // Rows in UPID order; one progress phase per layer list, then the limits.
  for (std::size_t i = 1; i < r->rows.size(); ++i)
    CHECK(r->rows[i - 1].scanned.upid < r->rows[i].scanned.upid);
  REQUIRE(phases.size() == 5);
  CHECK(phases[0].first == "UPID list OS");
  CHECK(phases[4].first == "min/max/default");
  CHECK(phases[4].second == params.size());
  // Read telegrams only.
  CHECK(rig.wire->write_telegrams() == 0);
}

TEST_CASE("db scan: layers can be chosen, no database leaves every name empty", "[db][scan]") {
  test::SimRig rig(kFixture);
  auto opt = scan_options();
  opt.names_from.clear();
  opt.layers = {false, true, false, false};
  auto r = ops::scan_drive_profile(*rig.client, db::Database::empty(), opt);
  REQUIRE(r.ok());
  std::size_t mc = 0;
  for (const auto& [upid, p] : rig.drive->state().params)
    if (upid >= 0x1000 && upid <= 0x1EFF) ++mc;
  CHECK(r->rows.size() == mc);
  for (const auto& row : r->rows) {
    CHECK(row.name.empty());
    CHECK(row.scanned.upid >= 0x1000);
    CHECK(row.scanned.upid <= 0x1EFF);
  }
  CHECK(r->per_layer[1] == mc);
}

TEST_CASE("db scan: profile ids are checked", "[db][scan]") {
  const auto& d = real_db();
  CHECK(ops::check_scan_profile_id("e1100-fw-x", d).ok());
  CHECK_FALSE(ops::check_scan_profile_id("", d).ok());
  CHECK_FALSE(ops::check_scan_profile_id("a b", d).ok());
  CHECK_FALSE(ops::check_scan_profile_id("a,b", d).ok());
  CHECK_FALSE(ops::check_scan_profile_id("*", d).ok());
  auto seeded = ops::check_scan_profile_id("e1100-mc-linrs", d);
  REQUIRE_FALSE(seeded.ok());
  CHECK(seeded.error().code == make_error_code(Errc::invalid_argument));
  // Nothing goes on the wire for a refused id.
  test::SimRig rig(kFixture);
  auto opt = scan_options();
  opt.profile.id = "e1100-mc-linrs";
  CHECK_FALSE(ops::scan_drive_profile(*rig.client, d, opt).ok());
  CHECK(rig.client->stats().requests == 0);
}

TEST_CASE("db scan: an interrupted scan resumes from the partial file with fewer telegrams",
          "[db][scan]") {
  const auto& d = real_db();
  // The uninterrupted reference.
  test::SimRig full(kFixture);
  auto ref = ops::scan_drive_profile(*full.client, d, scan_options());
  REQUIRE(ref.ok());
  const auto full_telegrams = full.client->stats().requests;

  const auto dir = scan_scratch("resume");
  const std::string partial = (dir / "scan.tsv.partial").string();
  std::size_t stored_after_cut = 0;
  {
    // The link closes in the middle of the min/max/default phase.
    test::SimRig cut(kFixture);
    cut.sim().faults().schedule(full_telegrams * 2 / 3, sim::Fault::close_link());
    auto store = ops::PartialFileStore::open(partial, kProfile);
    REQUIRE(store.ok());
    auto r = ops::scan_drive_profile(*cut.client, d, scan_options(store->get()));
    REQUIRE_FALSE(r.ok());
    CHECK(r.error().code == make_error_code(Errc::link_closed));
    stored_after_cut = (*store)->size();
    CHECK(stored_after_cut > 0);
    CHECK(stored_after_cut < ref->rows.size());
  }
  REQUIRE(fs::exists(partial));

  SECTION("rerun on a fresh link") {}
  SECTION("rerun after a torn last line") {
    std::ofstream(partial, std::ios::app | std::ios::binary) << "13C7\t000F\t00";
  }
  test::SimRig again(kFixture);
  auto store = ops::PartialFileStore::open(partial, kProfile);
  REQUIRE(store.ok());
  CHECK((*store)->loaded() == stored_after_cut);
  auto r = ops::scan_drive_profile(*again.client, d, scan_options(store->get()));
  REQUIRE(r.ok());
  CHECK(r->resumed == stored_after_cut);
  CHECK(r->asked == ref->rows.size() - stored_after_cut);
  REQUIRE(r->rows.size() == ref->rows.size());
  for (std::size_t i = 0; i < r->rows.size(); ++i) {
    CHECK(r->rows[i].scanned == ref->rows[i].scanned);
    CHECK(r->rows[i].name == ref->rows[i].name);
  }
  CHECK(ops::scan_fragment_tsv(*r) == ops::scan_fragment_tsv(*ref));
  const auto resumed_telegrams = again.client->stats().requests;
  CHECK(resumed_telegrams < full_telegrams);
  // Exactly the three limit queries per stored UPID were saved.
  CHECK(full_telegrams - resumed_telegrams == 3 * stored_after_cut);
  // The file now holds every UPID; removing it leaves nothing behind.
  CHECK((*store)->size() == ref->rows.size());
  REQUIRE((*store)->remove().ok());
  CHECK_FALSE(fs::exists(partial));
}

TEST_CASE("db scan: a partial file of another profile is refused", "[db][scan]") {
  const auto dir = scan_scratch("other-profile");
  const std::string partial = (dir / "x.partial").string();
  {
    auto s = ops::PartialFileStore::open(partial, "profile-a");
    REQUIRE(s.ok());
    REQUIRE((*s)->add({0x1000, 0x000F, 3, {1, 2, 3}}).ok());
  }
  auto other = ops::PartialFileStore::open(partial, "profile-b");
  REQUIRE_FALSE(other.ok());
  CHECK(other.error().code == make_error_code(Errc::invalid_argument));
  auto same = ops::PartialFileStore::open(partial, "profile-a");
  REQUIRE(same.ok());
  CHECK((*same)->loaded() == 1);
  // A stored entry is only used for the same type and address usage.
  CHECK((*same)->find(0x1000, 3, 0x000F) == ops::ScannedLimits{1, 2, 3});
  CHECK_FALSE((*same)->find(0x1000, 4, 0x000F));
  CHECK_FALSE((*same)->find(0x1000, 3, 0x000D));
  fs::path junk = dir / "junk.partial";
  std::ofstream(junk) << "hello\tworld\n";
  CHECK_FALSE(ops::PartialFileStore::open(junk.string(), "profile-a").ok());
}

TEST_CASE("db scan: the fragment compiles with the real compiler and the profile is queryable",
          "[db][scan]") {
  const auto& d = real_db();
  test::SimRig rig(kFixture);
  auto r = ops::scan_drive_profile(*rig.client, d, scan_options());
  REQUIRE(r.ok());
  const std::string fragment = ops::scan_fragment_tsv(*r);
  CHECK(fragment.find("#@profiles.tsv\tprofile\tfamily") != std::string::npos);

  const auto dir = scan_scratch("compile");
  const auto src = dir / "upid-db";
  fs::create_directories(src);
  for (const auto& e : fs::directory_iterator(fs::path(LMCFG_SOURCE_DIR) / "upid-db"))
    if (e.path().extension() == ".tsv") fs::copy_file(e.path(), src / e.path().filename());
  const std::size_t real_rows = d.parameters().size();

  SECTION("the fragment alone is ignored by the compiler (warning), so it is merged") {
    std::ofstream(src / "scan-e1100-fw-scantest.tsv", std::ios::binary) << fragment;
    auto rep = db::compile_upid_db(src.string(), "");
    CHECK(rep.ok());
    bool warned = false;
    for (const auto& dg : rep.diagnostics)
      if (dg.warning && dg.file.find("scan-e1100-fw-scantest.tsv") != std::string::npos)
        warned = true;
    CHECK(warned);
    CHECK(rep.counts["parameters"] == real_rows);
  }

  auto merged = ops::merge_scan_fragment(src.string(), fragment);
  REQUIRE(merged.ok());
  CHECK(merged->profile == kProfile);
  CHECK(merged->parameters_added == r->rows.size());
  CHECK(merged->parameters_replaced == 0);
  CHECK_FALSE(merged->profile_replaced);

  SECTION("merging a rescan replaces the earlier rows") {
    auto again = ops::merge_scan_fragment(src.string(), fragment);
    REQUIRE(again.ok());
    CHECK(again->parameters_replaced == r->rows.size());
    CHECK(again->profile_replaced);
  }

  const auto out = dir / "upid.sqlite";
  auto rep = db::compile_upid_db(src.string(), out.string());
  for (const auto& dg : rep.diagnostics) UNSCOPED_INFO(dg.str());
  REQUIRE(rep.ok());
  REQUIRE(rep.written);
  auto opened = db::Database::open(out.string());
  REQUIRE(opened.ok());
  const auto& nd = *opened;
  CHECK(nd.parameters().size() == real_rows + r->rows.size());
  const auto* prof = nd.profile(kProfile);
  REQUIRE(prof);
  CHECK(prof->prov.source == r->source);
  CHECK(prof->family == "E1100");
  CHECK(prof->prov.file == "profiles.tsv");
  for (const auto& [upid, p] : rig.drive->state().params) {
    INFO("UPID " << std::hex << upid);
    const auto* q = nd.find(upid, kProfile);
    REQUIRE(q);
    REQUIRE(q->profiles == std::vector<std::string>{kProfile});
    CHECK(q->prov.source == r->source);
    REQUIRE(q->spec.type);
    CHECK(static_cast<std::uint16_t>(*q->spec.type) == p.type);
    REQUIRE(q->address_usage);
    CHECK(q->address_usage->raw == p.address_usage);
    CHECK(q->spec.min == std::optional<std::int64_t>(decoded(p.type, p.min)));
    CHECK(q->spec.max == std::optional<std::int64_t>(decoded(p.type, p.max)));
    CHECK(q->default_value == std::optional<std::int64_t>(decoded(p.type, p.def)));
    if (const auto* k = d.find(upid, "e1100-mc-linrs")) {
      CHECK(q->name == k->name);
      CHECK(q->path == k->path);
      CHECK(q->spec.unit == k->spec.unit);
      CHECK(q->spec.scale == k->spec.scale);
      CHECK(q->comm == k->comm);
      REQUIRE(q->spec.labels.size() == k->spec.labels.size());
      for (std::size_t i = 0; i < k->spec.labels.size(); ++i) {
        CHECK(q->spec.labels[i].raw == k->spec.labels[i].raw);
        CHECK(q->spec.labels[i].label == k->spec.labels[i].label);
      }
    } else {
      CHECK(q->name.empty());
    }
    // The seed-derived definition stays as it was.
    if (const auto* k = d.find(upid, "e1100-mc-linrs"))
      CHECK(nd.find(upid, "e1100-mc-linrs")->prov.source == k->prov.source);
  }
}

TEST_CASE("db scan: merging refuses to replace a profile not made by a scan", "[db][scan]") {
  const auto dir = scan_scratch("refuse");
  fs::copy_file(fs::path(LMCFG_SOURCE_DIR) / "upid-db" / "profiles.tsv", dir / "profiles.tsv");
  fs::copy_file(fs::path(LMCFG_SOURCE_DIR) / "upid-db" / "parameters.tsv", dir / "parameters.tsv");
  const std::string before = slurp(dir / "parameters.tsv");
  std::string frag =
      "#@profiles.tsv\tprofile\tfamily\tsoftware\tversion\tdescription\tsource\n"
      "#@profiles.tsv\te1100-mc-linrs\tE1100\t\t\t\tscanned from a drive: e1100-mc-linrs "
      "2026-01-02 MACID 11h\n"
      "upid\tprofiles\tlayer\tname\tpath\ttype\taddress_"
      "usage\tmin\tmax\tdefault\tunit\tscale\tenum\tcomm\tdescription\t"
      "source\n";
  auto r = ops::merge_scan_fragment(dir.string(), frag);
  REQUIRE_FALSE(r.ok());
  CHECK(r.error().code == make_error_code(Errc::validation_failed));
  CHECK(slurp(dir / "parameters.tsv") == before);
  CHECK_FALSE(ops::merge_scan_fragment(dir.string(), "upid\tprofiles\n").ok());
}

}  // namespace ops_test_db_scan
