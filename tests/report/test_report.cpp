// lmcfg report (README), the page (lib/report/report.cpp): pages of the demo
// axis, of the diff between the demo axis and the used spare, and of two large
// configurations (5,000 parameters, 100 curves of 1,000 setpoints, 255 command
// table entries), each loaded in headless Chromium and checked in its DOM
// (tests/support/report_pages.hpp): every parameter row, the diff's
// highlighted rows exactly those `lmcfg diff --json` lists, no console error,
// no request leaving the file, `<script>` names shown as text; errors leave no
// file. Curves: test_report_curves.cpp; command table: test_report_ct.cpp.
#include <catch2/catch.hpp>
#include <chrono>
#include <nlohmann/json.hpp>
#include <string>

#include "../../bench/report_workload.hpp"
#include "config/config_io.hpp"
#include "db/database.hpp"
#include "ops/diff.hpp"
#include "report/report.hpp"
#include "report_pages.hpp"

// This file's own namespace: the test binary is a unity build (tests/CMakeLists.txt).
namespace report_test_report {

using namespace lmcfg;
using namespace lmcfg::test::report_pages;
using test::slurp;

TEST_CASE("html_escape: markup, quotes, control bytes and bad UTF-8 become text", "[report]") {
  CHECK(report::html_escape(kScript) == "&lt;script&gt;alert(1)&lt;/script&gt;");
  CHECK(report::html_escape("a\"b'c&d") == "a&quot;b&#39;c&amp;d");
  CHECK(report::html_escape("x\ny\x7F") == "x\\x0Ay\\x7F");
  CHECK(report::html_escape("\xC2\xB5m \xE2\x86\x92") == "\xC2\xB5m \xE2\x86\x92");
  CHECK(report::html_escape("\xFF\xC0\x80\xED\xA0\x80") == "\\xFF\\xC0\\x80\\xED\\xA0\\x80");
  CHECK(report::html_escape("\xE2\x86") == "\\xE2\\x86");  // truncated sequence
}

TEST_CASE("report of the demo axis: every parameter, curve and entry, in a browser", "[report]") {
  Demo d;
  const fs::path html = out_dir() / "demo-axis.html";
  fs::remove(html);
  const Out r = tool(d.w, "report " + q(d.axis) + " -o " + q(html));
  INFO(r.err);
  REQUIRE(r.rc == 0);
  CHECK(r.err.find("open file://") != std::string::npos);
  const std::string page = slurp(html);
  CHECK(page.find(kScript) == std::string::npos);  // the label is escaped
  CHECK(page.find("&lt;script&gt;alert(1)&lt;/script&gt;") != std::string::npos);
  CHECK(page.find("://") == std::string::npos);  // no URL at all
  const auto cfg = read(d.axis);
  REQUIRE(!cfg.curves.empty());
  REQUIRE(!cfg.ct_entries.empty());
  const json j = load_in_browser(d.w, html, "demo-axis.png", true);
  if (j.is_null()) return;
  check_param_rows(j, {&cfg});
  check_curves(j, cfg, nullptr);
  CHECK(j["ct"].size() == cfg.ct_entries.size());
  CHECK(j["diff"] == json::array());
  CHECK(j["texts"][kScript] == true);
}

TEST_CASE("report of the demo axis vs the used spare: highlighted rows are diff --json's",
          "[report]") {
  Demo d;
  check_diff_page(d.w, d.axis, d.spare, "", "demo-diff");
  check_diff_page(d.w, d.axis, d.spare, " --ignore-unit --ignore-metadata", "demo-diff-ignore");
}

TEST_CASE("report of two large configurations: curves overlaid, entries side by side",
          "[report][large]") {
  Work w;
  const auto a = reportbench::large_config();
  const auto b = reportbench::large_config_changed(a);
  const fs::path pa = w.path / "large-a.json", pb = w.path / "large-b.json";
  REQUIRE(config::write_config_file(a, pa.string(), config::FileFormat::json).ok());
  REQUIRE(config::write_config_file(b, pb.string(), config::FileFormat::json).ok());
  auto db = database();
  const auto t0 = std::chrono::steady_clock::now();
  const auto r = ops::diff(a, b, db ? *db : db::Database::empty(), {}, {});
  const std::string page =
      report::render_diff_report(a, "a", b, "b", r, db ? *db : db::Database::empty(), {});
  const double ms =
      std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - t0).count();
  WARN("large diff report: " << page.size() << " bytes, " << r.items.size()
                             << " differences, diff + render " << ms << " ms");
  CHECK(page.size() < 5u * 1000 * 1000);
  check_diff_page(w, pa, pb, "", "large-diff");
}

TEST_CASE("report: errors leave no file", "[report]") {
  Work w;
  const fs::path cfg = fs::path(LMCFG_SOURCE_DIR) / "tests/fixtures/config/everything.json";
  // An output directory that does not exist: refused before the drive is opened.
  Out r = tool(w, "report drive --port sim:" + q(w.path / "nothing.sim.json") + " -o " +
                      q(w.path / "missing/dir/r.html"));
  CHECK(r.rc == 2);
  CHECK(r.err.find("-o") != std::string::npos);
  // A bad input: exit 2, no partial output.
  r = tool(w, "report " + q(w.path / "absent.json") + " -o " + q(w.path / "r.html"));
  CHECK(r.rc == 2);
  CHECK(!fs::exists(w.path / "r.html"));
  r = tool(w, "report " + q(cfg) + " " + q(w.path / "absent.json") + " -o " + q(w.path / "r.html"));
  CHECK(r.rc == 2);
  CHECK(!fs::exists(w.path / "r.html"));
  // -o - writes the page to stdout; A vs itself is identical.
  r = tool(w, "report " + q(cfg) + " " + q(cfg) + " -o -");
  CHECK(r.rc == 0);
  CHECK(r.out.rfind("<!DOCTYPE html>", 0) == 0);
  CHECK(r.out.find("data-differences=\"0\"") != std::string::npos);
}

TEST_CASE("report: a diff page asked to open on the differences has the box ticked", "[report]") {
  const auto a = reportbench::large_config();
  const auto b = reportbench::large_config_changed(a);
  const auto r = ops::diff(a, b, db::Database::empty(), {}, {});
  const std::string box = "<input class=\"toggle\" type=\"checkbox\" id=\"only-diff\"";
  report::ReportOptions opt;
  CHECK(report::render_diff_report(a, "a", b, "b", r, db::Database::empty(), opt)
            .find(box + "><label") != std::string::npos);
  opt.only_differences = true;
  CHECK(report::render_diff_report(a, "a", b, "b", r, db::Database::empty(), opt)
            .find(box + " checked><label") != std::string::npos);
}

}  // namespace report_test_report
