// lmcfg report on the large configuration of the report benchmark (5,000 parameters, 100
// curves of 1,000 setpoints, 255 command table entries): generation time and
// file size of the one-configuration page and of the diff page against a
// changed copy, then (when Chromium and node are installed) the time the page
// takes to open in headless Chromium, through tests/browser/check-report.js.
// Prints the figures of docs/measurements.md. Not part of ctest.
//   lmcfg_bench_report [OUT_DIR]   (default: the current directory)
#include <algorithm>
#include <chrono>
#include <cstdio>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <nlohmann/json.hpp>
#include <string>
#include <vector>

#include "config/atomic_file.hpp"
#include "db/database.hpp"
#include "ops/diff.hpp"
#include "report/report.hpp"
#include "report_workload.hpp"

using namespace lmcfg;
namespace fs = std::filesystem;

namespace {

double median(std::vector<double> v) {
  std::sort(v.begin(), v.end());
  return v.empty() ? 0 : v[v.size() / 2];
}

template <class F>
double median_ms(int runs, F&& f) {
  std::vector<double> t;
  for (int i = 0; i < runs; ++i) {
    const auto t0 = std::chrono::steady_clock::now();
    f();
    t.push_back(
        std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - t0).count());
  }
  return median(t);
}

std::string chromium() {
  if (const char* e = std::getenv("LMCFG_CHROMIUM"); e && *e) return e;
  for (const char* c : {"/usr/bin/chromium", "/usr/bin/chromium-browser"})
    if (fs::exists(c)) return c;
  return "";
}

// Median over `runs` fresh browser loads: navigation start -> load event, and
// -> two animation frames after it (laid out and painted).
void browser(const fs::path& html, int runs) {
  const std::string chrome = chromium();
  if (chrome.empty() || std::system("node --version >/dev/null 2>&1") != 0) {
    std::printf("  browser: skipped (chromium or node not found)\n");
    return;
  }
  std::vector<double> load, render;
  const fs::path out = html.string() + ".json";
  for (int i = 0; i < runs; ++i) {
    const std::string cmd = "node '" LMCFG_SOURCE_DIR
                            "/tests/browser/check-report.js' --chromium '" +
                            chrome + "' --html '" + html.string() + "' --screenshot '" +
                            html.string() + ".png' >'" + out.string() + "'";
    if (std::system(cmd.c_str()) != 0) {
      std::printf("  browser: check-report.js failed\n");
      return;
    }
    std::ifstream f(out);
    const auto j = nlohmann::json::parse(f);
    load.push_back(j["load_ms"].get<double>());
    render.push_back(j["render_ms"].get<double>());
  }
  fs::remove(out);
  std::printf(
      "  Chromium (median of %d loads): load event %.0f ms, painted %.0f ms (min %.0f, max %.0f)\n",
      runs, median(load), median(render), *std::min_element(render.begin(), render.end()),
      *std::max_element(render.begin(), render.end()));
}

}  // namespace

int main(int argc, char** argv) {
  const fs::path dir = argc > 1 ? argv[1] : ".";
  fs::create_directories(dir);
  auto opened = db::Database::open(LMCFG_DB_PATH);
  const db::Database& db = opened.ok() ? *opened : db::Database::empty();
  const auto a = reportbench::large_config();
  const auto b = reportbench::large_config_changed(a);
  report::ReportOptions ro;
  ro.tool_version = "lmcfg_bench_report";

  std::string page;
  const double single =
      median_ms(9, [&] { page = report::render_report(a, "large.json", db, ro); });
  std::printf(
      "large configuration: 5000 parameters, 100 curves x 1000 setpoints, 255 CT entries\n");
  std::printf("  one configuration: %.1f ms to generate (median of 9), %zu bytes (%.2f MB)\n",
              single, page.size(), static_cast<double>(page.size()) / 1e6);
  const fs::path one = dir / "bench-large.html";
  if (auto w = config::write_file_atomic(one, page); !w.ok()) return 1;
  browser(one, 5);

  ops::DiffResult r;
  const double diffed = median_ms(9, [&] {
    r = ops::diff(a, b, db, {}, {});
    page = report::render_diff_report(a, "large-a.json", b, "large-b.json", r, db, ro);
  });
  std::printf(
      "  diff page (%zu differences): %.1f ms to compare and generate, %zu bytes (%.2f MB)\n",
      r.items.size(), diffed, page.size(), static_cast<double>(page.size()) / 1e6);
  const fs::path two = dir / "bench-large-diff.html";
  if (auto w = config::write_file_atomic(two, page); !w.ok()) return 1;
  browser(two, 5);
  return 0;
}
