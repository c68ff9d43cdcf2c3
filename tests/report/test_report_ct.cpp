// The report's command table (lib/report/report_ct.cpp): an entry the page
// cannot decode says why, and the chains the entries' links form are listed
// from each entry no other links to, then from the smallest entry of each
// remaining cycle, every entry once, with links to undefined entries marked.
#include <catch2/catch.hpp>
#include <cstdint>
#include <string>

#include "config/model.hpp"
#include "db/database.hpp"
#include "report/report.hpp"

// This file's own namespace: the test binary is a unity build (tests/CMakeLists.txt).
namespace report_test_report_ct {

using namespace lmcfg;

namespace {

// An entry of `n` bytes whose header links to `link` (0xFFFF: no link).
config::CtEntry entry(std::uint32_t id, std::uint16_t link, std::size_t n = 4) {
  config::CtEntry e;
  e.id = id;
  e.raw.assign(n, 0);
  e.raw[0] = 0x01;
  e.raw[1] = 0xA7;
  e.raw[2] = static_cast<std::uint8_t>(link & 0xFF);
  e.raw[3] = static_cast<std::uint8_t>(link >> 8);
  return e;
}

}  // namespace

TEST_CASE("report: command table entries that cannot be decoded say why, without a database",
          "[report]") {
  config::DriveConfig c;
  c.ct_entries.push_back(entry(7, 7));  // 4 bytes, links to itself
  const std::string one = report::render_report(c, "odd", db::Database::empty(), {});
  CHECK(one.find("not decoded (no UPID database)") != std::string::npos);
}

TEST_CASE("report: command table chains start where no entry links, cycles from their smallest",
          "[report]") {
  config::DriveConfig c;
  for (auto [id, link] : {std::pair<std::uint32_t, std::uint16_t>{1, 2},
                          {2, 3},
                          {3, 0xFFFF},
                          {5, 6},
                          {6, 5},
                          {8, 9},
                          {10, 0xFFFF}})
    c.ct_entries.push_back(entry(id, link));
  const std::string page = report::render_report(c, "chains", db::Database::empty(), {});
  const std::string arrow = " \xE2\x86\x92 ", back = " \xE2\x86\xBA ";
  auto a = [](int id) {
    return "<a href=\"#ct-" + std::to_string(id) + "\">" + std::to_string(id) + "</a>";
  };
  const std::string want = "<b>Linked entries:</b> " + a(1) + arrow + a(2) + arrow + a(3) + "; " +
                           a(8) + arrow + "9 <span class=\"bad\">(not defined)</span>; " + a(5) +
                           arrow + a(6) + back + "5</p>";
  CHECK(page.find(want) != std::string::npos);
}

}  // namespace report_test_report_ct
