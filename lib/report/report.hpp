#pragma once
// `lmcfg report` (README): a drive configuration, or the difference of two,
// as one self-contained HTML page for people: inline CSS and SVG only (no
// script, no external font or URL; a Content-Security-Policy forbids both),
// readable without JavaScript and printable (a print stylesheet, a page break
// before each section). Every text from a file or a drive is HTML-escaped;
// bytes that are not UTF-8 show as \xNN.
//
// One configuration: identity (drive, firmware, capture time, labels, tool
// and database versions); parameters per layer with name, value in scaled
// units and enum labels, factory default and a mark where they differ; each
// curve as an SVG plot (every setpoint marked, axes in the curve's units) with
// its info block decoded; the command table with names, decoded commands,
// links and the chains they form.
//
// Two configurations: the same page as a diff, built from ops::diff()'s
// result (the one `lmcfg diff` prints): every DiffItem is exactly one element
// with class "diff" (identity and scope rows, parameter rows, curve figures,
// command table rows), so the highlighted rows are the ones `lmcfg diff
// --json` lists, and the summary counts are those items.
//
// DOM contract (tests/browser/check-report.js relies on it):
//   tr.param[data-layer][data-upid]      one per parameter (diff: per UPID of either side)
//   figure.curve[data-curve-id]          one per curve (diff: per ID of either side)
//     polyline.setpoints[data-side][data-setpoints]  one vertex and one marker per setpoint
//   tr.ct[data-ct-id]                    one per command table entry
//   .diff[data-kind][data-key]           one per DiffItem; data-key is the
//       UPID (4 hex digits), the curve / entry ID, or the name (metadata, scope)
#include <string>

#include "config/model.hpp"
#include "ops/diff.hpp"

namespace lmcfg::db {
class Database;
}

namespace lmcfg::report {

struct ReportOptions {
  std::string tool_version;  // "lmcfg 0.1.0 (git abc123)"; "" = not shown
  std::string generated_at;  // ISO 8601 UTC; "" = not shown
  // A diff page opens with "show only the differences" ticked (the console's
  // diff pages): rows and curves without a difference are hidden until unticked.
  bool only_differences = false;
};

// One configuration. `name` is where it came from (file name, "drive").
std::string render_report(const config::DriveConfig& cfg, const std::string& name,
                          const db::Database& db, const ReportOptions& opt);

// Two configurations; `r` is ops::diff(a, b, ...) with the options the caller chose.
std::string render_diff_report(const config::DriveConfig& a, const std::string& a_name,
                               const config::DriveConfig& b, const std::string& b_name,
                               const ops::DiffResult& r, const db::Database& db,
                               const ReportOptions& opt);

// HTML text for any bytes: & < > " ' escaped; invalid UTF-8 and control
// characters as \xNN (so nothing from a file can open a tag or an attribute).
std::string html_escape(std::string_view s);

}  // namespace lmcfg::report
