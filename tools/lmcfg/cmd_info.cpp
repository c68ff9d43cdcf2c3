// lmcfg info: state, status/warn word bits, actual error and error log of a drive.
#include <cstdio>

#include "command.hpp"
#include "link_options.hpp"
#include "ops/drive_info.hpp"

namespace lmcfg::cli {
namespace {

int run(CommonOptions& o) {
  const db::Database db = load_database(o);
  auto session = open_link(o);
  if (!session.ok()) return fail("info", session.error());
  auto info = ops::read_drive_info((*session)->client(), db);
  auto closed = (*session)->close();
  if (!info.ok()) return session->fail("info", info.error());
  if (!closed.ok()) return session->fail("info", closed.error());
  std::fputs((o.json ? ops::render_info_json(*info) : ops::render_info(*info)).c_str(), stdout);
  return kOk;
}

}  // namespace

void add_info(CLI::App& app, int& exit_code) {
  auto o = std::make_shared<CommonOptions>();
  auto* sub = app.add_subcommand(
      "info", "Show a drive's state, status and warn words, actual error and error log");
  sub->footer("Example: lmcfg info --port /dev/ttyUSB0 --id 0x11");
  add_link_options(sub, *o);
  add_output_options(sub, *o);
  sub->callback([o, &exit_code] { exit_code = run(*o); });
}
}  // namespace lmcfg::cli
