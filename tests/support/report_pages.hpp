#pragma once
// The HTML report's tests (tests/report/test_report*.cpp): `lmcfg report` run
// as a program, its page loaded in headless Chromium
// (tests/browser/check-report.js) and its DOM facts checked against the
// configuration and against `lmcfg diff --json`. Pages and screenshots stay in
// BUILD/report-tests/ for people. Without Chromium the browser checks are
// skipped with a SKIP message, unless LMCFG_REQUIRE_BROWSER=1 (scripts/test.sh,
// which installs it) makes that a failure.
#include <unistd.h>

#include <catch2/catch.hpp>
#include <cstdlib>
#include <filesystem>
#include <map>
#include <nlohmann/json.hpp>
#include <optional>
#include <set>
#include <string>
#include <tuple>
#include <vector>

#include "browser.hpp"
#include "common/bytes.hpp"
#include "common/layers.hpp"
#include "config/config_io.hpp"
#include "db/database.hpp"
#include "files.hpp"

namespace lmcfg::test::report_pages {

namespace fs = std::filesystem;
using nlohmann::json;

inline const std::string kScript = "<script>alert(1)</script>";

inline fs::path out_dir() {
  const fs::path d = fs::path(LMCFG_BINARY_DIR) / "report-tests";
  fs::create_directories(d);
  return d;
}

// A directory of one test's own, removed afterwards.
struct Work : ScratchDir {
  Work() : ScratchDir("report") {}
};

inline std::string q(const fs::path& p) { return "'" + p.string() + "'"; }

struct Out {
  int rc = -1;
  std::string out, err;
};

inline Out run(const Work& w, const std::string& cmd) {
  const auto o = w.path / "stdout.txt", e = w.path / "stderr.txt";
  const int rc = std::system((cmd + " >" + q(o) + " 2>" + q(e)).c_str());
  return {WIFEXITED(rc) ? WEXITSTATUS(rc) : -1, slurp(o), slurp(e)};
}

inline Out tool(const Work& w, const std::string& args) {
  return run(w,
             std::string("LMCFG_UPID_DB='") + LMCFG_DB_PATH + "' " + LMCFG_TOOL_PATH + " " + args);
}

// The page's DOM facts, or null when the browser checks are skipped.
inline json load_in_browser(const Work& w, const fs::path& html, const std::string& shot_name,
                            bool full_page) {
  const std::string chromium = find_chromium();
  if (chromium.empty()) {
    if (browser_required()) FAIL("chromium not found, and LMCFG_REQUIRE_BROWSER=1");
    WARN("SKIP: browser checks of " << html.filename().string()
                                    << ": chromium not found (apt-get install chromium)");
    return nullptr;
  }
  const fs::path shot = out_dir() / shot_name;
  fs::remove(shot);
  std::string cmd = "node " + q(fs::path(LMCFG_SOURCE_DIR) / "tests/browser/check-report.js") +
                    " --chromium " + q(chromium) + " --html " + q(html) + " --screenshot " +
                    q(shot) + " --text '" + kScript + "' --text '<svg onload=alert(1)>'" +
                    " --text '<script>alert(1)</sc' --text '<script>alert(1'";
  if (full_page) cmd += " --full-page";
  const Out r = run(w, cmd);
  INFO(r.err);
  REQUIRE(r.rc == 0);
  json j = json::parse(r.out);
  CHECK(fs::file_size(shot) > 1000);
  // Nothing but the page itself, no script, no error.
  CHECK(j["console_errors"] == json::array());
  CHECK(j["requests"] == json::array());
  CHECK(j["dialogs"] == json::array());
  CHECK(j["scripts"] == 0);
  CHECK(j["handlers"] == 0);
  CHECK(j["externalRefs"] == json::array());
  return j;
}

// Every parameter of the configuration has its row, once.
inline void check_param_rows(const json& page,
                             const std::vector<const config::DriveConfig*>& sides) {
  std::multiset<std::pair<std::string, std::string>> seen, want;
  for (const auto& p : page["params"])
    seen.insert({p[0].get<std::string>(), p[1].get<std::string>()});
  std::set<std::pair<std::string, std::string>> all;
  for (const auto* c : sides)
    for (int l = 1; l <= lmcfg::layers::kCount; ++l)
      for (const auto& p : c->layer(l))
        all.insert({std::string(lmcfg::layers::name(l)), hex(p.upid, 4)});
  want.insert(all.begin(), all.end());
  CHECK(seen.size() == want.size());
  CHECK(seen == want);
}

// One figure per curve; each side's polyline has one vertex and one marker per setpoint.
inline void check_curves(const json& page, const config::DriveConfig& a,
                         const config::DriveConfig* b) {
  std::map<std::uint32_t, json> figs;
  for (const auto& f : page["curves"]) {
    CHECK(figs.count(f["id"]) == 0);
    figs[f["id"]] = f;
  }
  std::set<std::uint32_t> ids;
  for (const auto& c : a.curves) ids.insert(c.id);
  if (b)
    for (const auto& c : b->curves) ids.insert(c.id);
  REQUIRE(figs.size() == ids.size());
  for (auto id : ids) {
    INFO("curve " << id);
    REQUIRE(figs.count(id));
    const json& f = figs[id];
    const config::Curve* ca = a.find_curve(id);
    const config::Curve* cb = b ? b->find_curve(id) : nullptr;
    const bool changed = b && !(ca && cb && *ca == *cb);
    CHECK(f["diff"] == changed);
    std::map<std::string, std::size_t> want;
    auto count = [](const config::Curve& c) { return config::decode_curve(c)->setpoints.size(); };
    if (ca) want["a"] = count(*ca);
    if (cb && (changed || !ca)) want["b"] = count(*cb);
    REQUIRE(f["polylines"].size() == want.size());
    for (const auto& p : f["polylines"]) {
      const std::string side = p["side"];
      CHECK(p["vertices"] == want[side]);
      CHECK(p["setpoints"] == want[side]);
      CHECK(p["markers"] == true);
      CHECK(p["width"].get<double>() > 100);  // drawn across the plot
    }
  }
}

inline std::optional<db::Database> database() {
  auto d = db::Database::open(LMCFG_DB_PATH);
  if (!d.ok()) return std::nullopt;
  return std::move(*d);
}

// The demo axis and the used spare, backed up from their simulated drives as scripts/demo.sh does.
struct Demo {
  Work w;
  fs::path axis, spare;
  Demo() {
    const fs::path sim = fs::path(LMCFG_SOURCE_DIR) / "tests/fixtures/sim";
    fs::copy_file(sim / "commissioned-axis.json", w.path / "axis.sim.json");
    fs::copy_file(sim / "used-spare.json", w.path / "spare.sim.json");
    axis = w.path / "axis.json";
    spare = w.path / "spare.json";
    Out r = tool(w, "backup --quiet --port sim:" + q(w.path / "axis.sim.json") +
                        " --label 'machine=" + kScript + "' --label axis=X -o " + q(axis));
    INFO(r.err);
    REQUIRE(r.rc == 0);
    r = tool(w, "backup --quiet --port sim:" + q(w.path / "spare.sim.json") + " -o " + q(spare));
    INFO(r.err);
    REQUIRE(r.rc == 0);
  }
};

inline config::DriveConfig read(const fs::path& p) {
  auto c = config::read_config_file(p.string());
  REQUIRE(c.ok());
  return *c;
}

// `lmcfg report A B OPTS` in a browser: the highlighted elements are exactly
// `lmcfg diff --json A B OPTS`'s differences, every row and curve is there.
inline void check_diff_page(const Work& w, const fs::path& pa, const fs::path& pb,
                            const std::string& opts, const std::string& stem) {
  INFO("report " << stem << " options:" << opts);
  const fs::path html = out_dir() / (stem + ".html");
  fs::remove(html);
  const Out r = tool(w, "report " + q(pa) + " " + q(pb) + opts + " -o " + q(html));
  INFO(r.err);
  REQUIRE(r.rc == 0);
  const Out dj = tool(w, "diff --json " + q(pa) + " " + q(pb) + opts);
  REQUIRE(dj.rc == 1);
  const json diff = json::parse(dj.out);
  std::multiset<std::tuple<std::string, std::string, std::string>> want;
  for (const auto& it : diff["differences"]) {
    const std::string kind = it["kind"];
    if (kind == "parameter")
      want.insert({kind, it["upid"], it["layer"]});
    else if (kind == "curve" || kind == "ct_entry")
      want.insert({kind, std::to_string(it["id"].get<int>()), ""});
    else
      want.insert({kind, it["name"], ""});
  }
  REQUIRE(!want.empty());
  const auto a = read(pa), b = read(pb);
  const json j = load_in_browser(w, html, stem + ".png", true);
  if (j.is_null()) return;
  std::multiset<std::tuple<std::string, std::string, std::string>> seen;
  for (const auto& e : j["diff"])
    seen.insert({e[0].get<std::string>(), e[1].get<std::string>(), e[2].get<std::string>()});
  CHECK(seen == want);
  CHECK(j["verdict"] == diff["differences"].size());
  check_param_rows(j, {&a, &b});
  check_curves(j, a, &b);
  CHECK(j["texts"][kScript] == true);
  std::set<int> ct_ids, ct_rows;
  for (const auto* c : {&a, &b})
    for (const auto& e : c->ct_entries) ct_ids.insert(static_cast<int>(e.id));
  for (const auto& id : j["ct"]) CHECK(ct_rows.insert(id.get<int>()).second);
  CHECK(ct_rows == ct_ids);
}

}  // namespace lmcfg::test::report_pages
