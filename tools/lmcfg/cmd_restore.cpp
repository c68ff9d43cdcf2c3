// lmcfg restore FILE: plan (checks, no writes), execute, verify.
#include "command.hpp"
#include "config/config_io.hpp"
#include "devicenet_flow.hpp"
#include "link_options.hpp"
#include "ops/interrupt.hpp"
#include "restore_flow.hpp"

namespace lmcfg::cli {
namespace {

struct RestoreCli {
  CommonOptions common;
  std::string file;
  RestoreFlags flags;
};

int run(RestoreCli& o) {
  // From the start: a signal before the link opens stops the plan before its
  // first telegram, with the message and exit 130, instead of killing silently.
  ops::install_interrupt_handlers();
  // The file first: a bad file never opens the link, so nothing is written.
  auto file = config::read_config_file(o.file);
  if (!file.ok()) return fail("restore", file.error());
  const db::Database db = load_database(o.common);
  if (is_devicenet(o.common)) return restore_devicenet(*file, o.file, o.common, o.flags, db);
  auto overrides = relink_overrides(o.flags.reconnect);
  if (!overrides.ok()) return fail("restore", overrides.error());
  auto session = open_link(o.common, &ops::interrupt_flag());
  if (!session.ok()) return fail("restore", session.error());
  ops::RestoreOutcome out;
  const int code =
      restore_on_session(**session, *file, o.file, o.common, o.flags, *overrides, db, out);
  if (auto c = (*session)->close(); !c.ok()) return session->fail("restore", c.error());
  return code;
}

}  // namespace

void add_restore(CLI::App& app, int& exit_code) {
  auto o = std::make_shared<RestoreCli>();
  auto* sub = app.add_subcommand("restore",
                                 "Restore a configuration file onto a drive: plan, write, verify");
  sub->footer(
      "Examples:\n"
      "  lmcfg restore axis1.json --port /dev/ttyUSB0 --id 0x11 --dry-run\n"
      "  lmcfg restore axis1.json --port /dev/ttyUSB0 --id 0x11\n"
      "The plan checks every item against the drive and the database before any write; any "
      "problem\n"
      "refuses the restore (exit 3, nothing written). Only what differs is written; a drive that\n"
      "already matches gets no write at all. On a terminal the plan is shown and confirmed unless\n"
      "--yes; without a terminal --yes is required (exit 2). After writing, the drive is read "
      "back\n"
      "(exit 6 on a mismatch). Ctrl-C stops between two telegrams (exit 130) and names the step;\n"
      "the same restore run again converges.");
  sub->add_option("FILE", o->file, "configuration file (.json or .xml)")->required();
  add_link_options(sub, o->common);
  add_devicenet_options(sub, o->common);
  add_output_options(sub, o->common);
  add_restore_flags(sub, o->flags);
  sub->callback([o, &exit_code] { exit_code = run(*o); });
}
}  // namespace lmcfg::cli
