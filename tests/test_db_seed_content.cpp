// The UPID database's content against the seeds: row counts per table (so an
// edit of upid-db/*.tsv cannot silently drop rows; upid-db/EXTRACTION.md has
// the per-section counts) and spot values read off the seeds themselves.
#include <catch2/catch.hpp>

#include "db/ct_entry.hpp"
#include "db/database.hpp"

using namespace lmcfg;
using namespace lmcfg::db;

namespace {
const Database& real_db() {
  static auto db = Database::open(LMCFG_DB_PATH);
  REQUIRE(db.ok());
  return *db;
}
}  // namespace

TEST_CASE("upid-db: row counts of the extraction from seeds 001 and 003", "[db][seed]") {
  const auto& counts = real_db().info().counts;
  CHECK(counts.at("profiles") == 3);
  CHECK(counts.at("parameters") == 92);  // 82 from seed 001, 10 from seed 003
  CHECK(counts.at("errors") == 93);      // 85 MC codes 0000-008A, 8 LinRS states
  CHECK(counts.at("motion_commands") == 215);
  CHECK(counts.at("motion_command_params") == 469);
}

TEST_CASE("upid-db: seed 003 §10.1 13A2h is UINT16, min 0, max 65535, default 15", "[db][seed]") {
  const Parameter* p = real_db().find(0x13A2);
  REQUIRE(p != nullptr);
  CHECK(p->name == "P Gain Position Controller Set A");
  CHECK(p->layer == Layer::MC);
  REQUIRE(p->spec.type);
  CHECK(*p->spec.type == TypeCode::UInt16);
  CHECK(p->spec.min == 0);
  CHECK(p->spec.max == 65535);
  CHECK(p->default_value == 15);
  CHECK(p->prov.source.find("seed003") != std::string::npos);
}

TEST_CASE("upid-db: seed 003 §10.2/§15 LinRS parameters are communication parameters", "[db][seed]") {
  for (std::uint16_t upid : {std::uint16_t{0x200E}, std::uint16_t{0x2012}, std::uint16_t{0x206C}, std::uint16_t{0x2076}}) {
    const Parameter* p = real_db().find(upid);
    REQUIRE(p != nullptr);
    CHECK(p->comm);
    CHECK(p->layer == Layer::Intf);
  }
  CHECK(real_db().find(0x2012)->path == "LinRS\\RS Config\\Baud Rate\\Baud Rate Parameter Def");
  CHECK(real_db().find(0x2012)->format(8) == "38400 Baud (8)");
}

TEST_CASE("upid-db: error texts of seed 001 §10 and seed 003 §16.1", "[db][seed]") {
  const ErrorEntry* e = real_db().error("mc", 0x0001);
  REQUIRE(e != nullptr);
  CHECK(e->text == "Err: X4 Logic Supply Too Low");  // also the §14.2 capture's text
  REQUIRE(real_db().error("mc", 0x000C) != nullptr);
  CHECK(real_db().error("mc", 0x000C)->text == "Err: Pos Lag Standing Too Big");
  REQUIRE(real_db().error("linrs", 0xC8) != nullptr);
  CHECK(real_db().error("linrs", 0xC8)->text == "Parameter Unknown UPID");
}

TEST_CASE("upid-db: the motion command catalogue decodes seed 003 §12.1 entry 2", "[db][seed]") {
  const MotionCommand* c = real_db().motion_command(0x0100);
  REQUIRE(c != nullptr);
  CHECK(c->name == "VAI Go To Pos");
  REQUIRE(c->params.size() == 4);
  CHECK(c->params[0].offset == 2);
  CHECK(c->params[0].name == "Target Position");
}
