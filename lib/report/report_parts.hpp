#pragma once
// Internal to the HTML report (report/report.cpp, report_curves.cpp, report_ct.cpp).
#include <cstdint>
#include <string>

#include "config/model.hpp"
#include "ops/diff.hpp"

namespace lmcfg::db {
class Database;
}

namespace lmcfg::report {
// The report draws the comparison of ops::diff (lmcfg diff's).
using ops::DiffItem;
using ops::DiffResult;
}  // namespace lmcfg::report

namespace lmcfg::report::parts {

// "13A2" (four hex digits, no suffix).
// ' class="... diff" data-kind="parameter" data-key="13A2"' for a DiffItem.
std::string diff_key(const DiffItem& it);

// The <defs> every plot refers to (setpoint markers of side A and B).
std::string curve_defs();
// One figure per curve: the plot and the decoded info block.
void curve_figure(std::string& out, const config::Curve& c);
// A curve in a diff: A and B overlaid with a legend, plus B - A when both have
// the same number of setpoints. `item` is the curve's DiffItem (nullptr when
// the curve is the same on both sides).
void curve_figure_diff(std::string& out, const config::Curve* a, const config::Curve* b,
                       const DiffItem* item);

// The command table of one configuration: chains and a row per entry.
void ct_section(std::string& out, const config::DriveConfig& cfg, const db::Database& db);
// Side by side; the entries' DiffItems come from `r`.
void ct_section_diff(std::string& out, const config::DriveConfig& a, const config::DriveConfig& b,
                     const DiffResult& r, const db::Database& db);

}  // namespace lmcfg::report::parts
