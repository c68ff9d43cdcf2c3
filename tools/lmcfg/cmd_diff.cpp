// lmcfg diff A B: compare two configurations; each side is a file, `defaults`
// or `drive` (read live through the link options). Exit 0 identical, 1
// different, 2 or more on error, like diff(1).
#include <cstdio>

#include "command.hpp"
#include "compare.hpp"
#include "ops/diff.hpp"

namespace lmcfg::cli {
namespace {

int run(CompareOptions& o) {
  const db::Database db = load_database(o.common);
  Compared c;
  if (int rc = load_and_compare("diff", o, db, c); rc != kOk) return rc;
  const auto& result = *c.result;
  std::fputs((o.common.json ? ops::render_json(result, c.a_name, c.b_name)
                            : ops::render_text(result, c.a_name, c.b_name))
                 .c_str(),
             stdout);
  return result.identical() ? kOk : kDifferent;
}

}  // namespace

void add_diff(CLI::App& app, int& exit_code) {
  auto o = std::make_shared<CompareOptions>();
  auto* sub = app.add_subcommand(
      "diff", "Compare two configurations (files, factory defaults or a live drive)");
  sub->footer(
      "A and B are each a file (.json/.xml; '-' reads standard input, format from the "
      "content), 'defaults' (factory defaults, within the other side's scope) or 'drive' (read "
      "live).\n"
      "A side that captured a layer, the curves or the command table the other did not is a "
      "difference\n"
      "(scope); values that do not fit their type or range are flagged INVALID on their side.\n"
      "DeviceNet controller captures (seed 000) are compared value by value per motor; their\n"
      "live values only with --live. A DeviceNet and a LinRS capture are not comparable.\n"
      "Examples:\n"
      "  lmcfg diff axis1.json axis2.json\n"
      "  lmcfg diff defaults axis1.json\n"
      "  lmcfg diff axis1.json drive --port /dev/ttyUSB0 --id 0x11\n"
      "  ssh host cat axis1.xml | lmcfg diff - axis1.json\n"
      "  lmcfg report axis1.json axis2.json -o diff.html   (the same comparison as a page)\n"
      "Exit status: 0 identical, 1 different, 2 or more on error.");
  add_compare_options(sub, *o, true, true);
  sub->callback([o, &exit_code] { exit_code = run(*o); });
}
}  // namespace lmcfg::cli
