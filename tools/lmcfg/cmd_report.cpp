// lmcfg report A [B] -o report.html: a configuration (or the difference of
// two, compared exactly as `lmcfg diff` compares them) as one self-contained
// HTML page with curve plots, for people: open it in a browser, print it,
// attach it to a ticket. The page is built by report::render_report /
// render_diff_report; this main only loads the sides and writes the file.
#include <cstdio>
#include <filesystem>

#include "build_info.hpp"
#include "command.hpp"
#include "common/version.hpp"
#include "compare.hpp"
#include "config/atomic_file.hpp"
#include "ops/backup.hpp"
#include "report/report.hpp"

namespace lmcfg::cli {
namespace {

struct ReportCli {
  CompareOptions cmp;
  std::string output;
};

int run(ReportCli& o) {
  // Checked before a drive is talked to: nothing is read only to be lost.
  if (auto ok = check_output_path(o.output, "-o"); !ok.ok()) return fail("report", ok.error());
  const db::Database db = load_database(o.cmp.common);
  Compared c;
  if (int rc = load_and_compare("report", o.cmp, db, c); rc != kOk) return rc;

  report::ReportOptions ro;
  ro.tool_version = std::string("lmcfg ") + kToolVersion;
  if (*kGitRevision) ro.tool_version += std::string(" (git ") + kGitRevision + ")";
  ro.generated_at = ops::utc_now();
  const std::string html =
      c.b ? report::render_diff_report(c.a, c.a_name, *c.b, c.b_name, *c.result, db, ro)
          : report::render_report(c.a, c.a_name, db, ro);
  if (o.output == "-") {
    std::fwrite(html.data(), 1, html.size(), stdout);
    return std::fflush(stdout) == 0
               ? kOk
               : fail("report", Error(Errc::file_error, "-o -: cannot write to stdout"));
  }
  if (auto w = config::write_file_atomic(o.output, html); !w.ok()) return fail("report", w.error());
  if (!o.cmp.common.quiet) {
    std::error_code ec;
    const auto abs = std::filesystem::absolute(o.output, ec);
    std::string what = "a report of " + c.a_name;
    if (c.result)
      what = c.result->identical() ? "identical configurations"
                                   : std::to_string(c.result->items.size()) + " difference(s)";
    std::fprintf(stderr, "lmcfg report: wrote %s (%zu bytes, %s); open file://%s in a browser\n",
                 o.output.c_str(), html.size(), what.c_str(),
                 (ec ? o.output : abs.string()).c_str());
  }
  return kOk;
}

}  // namespace

void add_report(CLI::App& app, int& exit_code) {
  auto o = std::make_shared<ReportCli>();
  auto* sub = app.add_subcommand(
      "report", "Write a configuration, or the diff of two, as one HTML page with curve plots");
  sub->footer(
      "A and B are what 'lmcfg diff' accepts: a file (.json/.xml; '-' reads standard input), "
      "'defaults'\n"
      "(factory defaults, within the other side's scope) or 'drive' (read live through the "
      "link options).\n"
      "With A only: identity, parameters per layer (value, factory default, a mark where they "
      "differ),\n"
      "every curve as an SVG plot (each setpoint marked, axes in the curve's units), the "
      "command table\n"
      "(names, decoded motion commands, links and chains).\n"
      "With A and B: the same page as a diff, compared exactly as 'lmcfg diff A B' compares "
      "(same options):\n"
      "changed, added and removed rows highlighted old -> new, differing curves overlaid with "
      "B - A,\n"
      "command table entries side by side, a summary whose count is diff's number of "
      "differences.\n"
      "The page is self-contained (inline CSS and SVG, no script, fonts or URLs), printable, "
      "and shows\n"
      "every text from the file or drive escaped. The file is written atomically; '-o -' writes "
      "stdout.\n"
      "Examples:\n"
      "  lmcfg report axis1.json -o axis1.html\n"
      "  lmcfg report axis1.json spare.json --ignore-unit -o diff.html\n"
      "  lmcfg report defaults axis1.json -o changed-from-defaults.html\n"
      "  lmcfg report axis1.json drive --port /dev/ttyUSB0 --id 0x11 -o check.html\n"
      "Exit status: 0 written (whether or not A and B differ), 2 bad input or output path, 4 "
      "communication\n"
      "failure, 5 the drive refused; nothing is written on an error.");
  add_compare_options(sub, o->cmp, false, false);
  sub->add_option("-o,--output", o->output, "the HTML file to write ('-': standard output)")
      ->required();
  sub->callback([o, &exit_code] { exit_code = run(*o); });
}
}  // namespace lmcfg::cli
