// lmcfg undo [FILE] / lmcfg undo --list: put back what a writing command saved
// before its first write (ops/undo.hpp), through the normal restore.
#include <cstdio>

#include "command.hpp"
#include "config/config_io.hpp"
#include "link_options.hpp"
#include "ops/interrupt.hpp"
#include "ops/recovery.hpp"
#include "ops/undo.hpp"
#include "report/json_reports.hpp"
#include "restore_flow.hpp"

namespace lmcfg::cli {
namespace {

struct UndoCli {
  CommonOptions common;
  std::string file;
  bool list = false;
  RestoreFlags flags;
  CLI::Option* port = nullptr;
};

int run_list(const UndoCli& o, const std::filesystem::path& dir) {
  std::string drive;
  if (o.port->count() > 0) {
    auto lo = link_options(o.common);
    if (!lo.ok()) return fail("undo", lo.error());
    drive = ops::drive_key(o.common.port, lo->client.id);
  }
  auto records = ops::list_undo(dir, drive);
  if (!records.ok()) return fail("undo", records.error());
  if (o.common.json) {
    std::printf("%s\n", report::undo_list_json(dir, *records).dump(2).c_str());
    return kOk;
  }
  if (records->empty()) {
    std::printf("no undo records%s in %s\n", drive.empty() ? "" : (" of " + drive).c_str(),
                dir.string().c_str());
    return kOk;
  }
  std::string last;
  for (const auto& r : *records) {
    if (r.drive != last) std::printf("%s%s:\n", last.empty() ? "" : "\n", r.drive.c_str());
    last = r.drive;
    std::printf("  %s  %-13s  %s\n      %s\n", r.time.c_str(), r.command.c_str(),
                r.path.string().c_str(), r.holds.c_str());
  }
  return kOk;
}

int run(UndoCli& o) {
  ops::install_interrupt_handlers();
  auto dir = ops::undo_dir();
  if (!dir.ok()) return fail("undo", dir.error());
  if (o.list) {
    if (!o.file.empty())
      return fail("undo", Error(Errc::invalid_argument,
                                "--list takes no FILE (it lists every record, or those of the "
                                "drive the link options name)"));
    return run_list(o, *dir);
  }
  if (o.port->count() == 0)
    return fail("undo", Error(Errc::invalid_argument,
                              "--port is required: the drive to put the record back onto (or "
                              "--list to see the records)"));
  if (is_devicenet(o.common))
    return fail("undo", Error(Errc::invalid_argument,
                              "DeviceNet controllers have no undo records (a restore there writes "
                              "runtime values only, seed 000 §1.1); restore a backup instead"));
  auto lo = link_options(o.common);
  if (!lo.ok()) return fail("undo", lo.error());
  std::string file = o.file;
  if (file.empty()) {
    const std::string drive = ops::drive_key(o.common.port, lo->client.id);
    auto records = ops::list_undo(*dir, drive);
    if (!records.ok()) return fail("undo", records.error());
    if (records->empty())
      return fail("undo",
                  Error(Errc::not_found, "no undo record of drive " + o.common.id + " on " +
                                             o.common.port + " in " + (*dir / drive).string() +
                                             " (lmcfg undo --list shows every record)"));
    file = records->front().path.string();
  }
  auto cfg = config::read_config_file(file);
  if (!cfg.ok()) return fail("undo", cfg.error());
  const db::Database db = load_database(o.common);
  auto overrides = relink_overrides(o.flags.reconnect);
  if (!overrides.ok()) return fail("undo", overrides.error());
  auto session = open_link(o.common, &ops::interrupt_flag());
  if (!session.ok()) return fail("undo", session.error());
  if (!o.common.quiet && !o.common.json) std::fprintf(stderr, "undo: restoring %s\n", file.c_str());
  ops::RestoreOutcome out;
  const int code =
      restore_on_session(**session, *cfg, file, o.common, o.flags, *overrides, db, out);
  if (auto c = (*session)->close(); !c.ok()) return session->fail("undo", c.error());
  return code;
}

}  // namespace

void add_undo(CLI::App& app, int& exit_code) {
  auto o = std::make_shared<UndoCli>();
  o->flags.undo_name = "undo";
  auto* sub = app.add_subcommand(
      "undo", "Put back what restore, default or set --rom overwrote (saved before each write)");
  sub->footer(
      "Examples:\n"
      "  lmcfg undo --list\n"
      "  lmcfg undo --port /dev/ttyUSB0 --id 0x11\n"
      "  lmcfg undo ~/.local/state/lmcfg/undo/_dev_ttyUSB0-11h/20261124T171500Z-restore.json "
      "--port /dev/ttyUSB0 --id 0x11\n"
      "Before its first write, restore, fleet restore, default, set --rom and undo itself save "
      "what\n"
      "they change on the drive in $XDG_STATE_HOME/lmcfg/undo/<port>-<MACID>/ (else\n"
      "~/.local/state/lmcfg/undo/), the newest 10 per drive. Without FILE, undo restores the\n"
      "newest record of the drive the link options name, through the normal restore (plan,\n"
      "confirmation or --yes, write, verify; the exit codes of lmcfg restore). It saves a record\n"
      "of its own first, so an undo can be undone. --list: the records, newest first, per drive\n"
      "(only this drive's with --port).");
  sub->add_option("FILE", o->file, "an undo record (default: the drive's newest)");
  sub->add_flag("--list", o->list, "list the undo records, newest first, per drive");
  add_link_options(sub, o->common);
  add_devicenet_options(sub, o->common);
  o->port = sub->get_option("--port");
  o->port->required(false);
  add_output_options(sub, o->common);
  add_restore_flags(sub, o->flags);
  sub->callback([o, &exit_code] { exit_code = run(*o); });
}
}  // namespace lmcfg::cli
