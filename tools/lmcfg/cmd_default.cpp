// lmcfg default: set chosen layers to factory defaults, optionally delete curves and the command
// table.
#include <cstdio>

#include "audit_flow.hpp"
#include "command.hpp"
#include "common/layers.hpp"
#include "confirm.hpp"
#include "link_options.hpp"
#include "ops/factory_reset.hpp"
#include "ops/interrupt.hpp"
#include "ops/recovery.hpp"
#include "report/json_reports.hpp"
#include "restore_flow.hpp"

namespace lmcfg::cli {
namespace {

struct DefaultCli {
  CommonOptions common;
  std::string layers;
  bool curves = false;
  bool ct = false;
  bool include_comm = false;
  bool yes = false;
  bool no_undo = false;
  AuditFlags audit;
};

int run(DefaultCli& o) {
  ops::DefaultOptions d;
  if (!o.layers.empty()) {
    auto l = parse_layers(o.layers);
    if (!l.ok()) return fail("default", l.error());
    d.layers = *l;
  }
  d.curves = o.curves;
  d.command_table = o.ct;
  d.include_comm = o.include_comm;
  if (o.layers.empty() && !o.curves && !o.ct) {
    return fail("default", Error(Errc::invalid_argument,
                                 "nothing to do: give --layers, --curves and/or --ct"));
  }
  auto consent = confirm("Set " + (o.layers.empty() ? std::string() : "layers " + o.layers) +
                             (o.curves ? ", delete all curves" : "") +
                             (o.ct ? ", delete the command table" : "") + " of drive " +
                             o.common.id + " on " + o.common.port + " to factory defaults?",
                         "default a drive", o.yes);
  if (!consent.ok()) return fail("default", consent.error());
  if (*consent == ops::Consent::declined) {
    std::fprintf(stderr, "cancelled; nothing written\n");
    return kOk;
  }
  const db::Database db = load_database(o.common);
  auto lo = link_options(o.common);
  if (!lo.ok()) return fail("default", lo.error());
  auto record = ops::recovery_path("default", o.common.port, lo->client.id);
  if (!record.ok()) return fail("default", record.error());
  d.recovery_path = *record;
  d.port = o.common.port;
  if (!o.no_undo) {
    auto dir = ops::undo_dir();
    if (!dir.ok()) return fail("default", dir.error());
    d.undo = ops::UndoOptions{true, *dir, o.common.port, lo->client.id, "default", ops::kUndoKeep};
  }
  auto session = open_link(o.common, &ops::interrupt_flag());
  if (!session.ok()) return fail("default", session.error());
  ops::install_interrupt_handlers();
  auto& client = (*session)->client();
  ProgressBar bar(o.common);
  d.progress = bar.callback();
  auto rep = ops::default_drive(client, d, db);
  bar.end();
  auto closed = (*session)->close();
  {
    ops::JournalEntry e;
    e.audit = audit_of(o.audit);
    e.command = "default";
    e.port = o.common.port;
    e.macid = client.options().id;
    e.steps = report::default_steps_json(d, rep.ok() ? &*rep : nullptr, db);
    const Error* error = !rep.ok() ? &rep.error() : !closed.ok() ? &closed.error() : nullptr;
    e.outcome = error ? "failed" : "defaulted";
    e.exit_code = error ? exit_code_for(*error) : kOk;
    if (error) e.error = error->message;
    if (rep.ok() && rep->undo) e.undo = rep->undo->path.string();
    record_in_journal("default", std::move(e));
  }
  if (!rep.ok()) {
    if (o.common.json)
      std::printf("%s\n",
                  report::default_json("failed", nullptr, db, rep.error().message).dump(2).c_str());
    return session->fail("default", rep.error());
  }
  if (!closed.ok()) return session->fail("default", closed.error());
  if (rep->undo) print_undo_saved(*rep->undo, o.common);
  if (o.common.json) {
    std::printf("%s\n", report::default_json("defaulted", &*rep, db, "").dump(2).c_str());
  } else if (!o.common.quiet) {
    if (!rep->recovery_note.empty())
      std::fprintf(stderr, "recovery: %s\n", rep->recovery_note.c_str());
    for (const auto& s : rep->done) std::fprintf(stderr, "done: %s\n", s.c_str());
    // docs/field.md "Slow saves": each one read back before success.
    for (const auto& u : rep->unacknowledged)
      std::fprintf(stderr, "note: %s; the read-back confirmed it\n", u.c_str());
    if (rep->link_may_change)
      std::fprintf(stderr,
                   "note: communication parameters are at their factory defaults: the drive now "
                   "takes its MACID "
                   "and baud rate from its hex switches S2 and S1 (seed 003 §3.2)\n");
  }
  return kOk;
}

}  // namespace

void add_default(CLI::App& app, int& exit_code) {
  auto o = std::make_shared<DefaultCli>();
  auto* sub = app.add_subcommand(
      "default", "Set layers to factory defaults; optionally delete curves and command table");
  sub->footer(
      "Examples:\n"
      "  lmcfg default --port /dev/ttyUSB0 --layers mc,appl --yes\n"
      "  lmcfg default --port /dev/ttyUSB0 --layers os,mc,intf,appl --curves --ct\n"
      "Stops MC, defaults, deletes and saves to flash as asked, starts MC and resets. The drive's\n"
      "communication parameters are kept unless --include-comm: read first, recorded in\n"
      "$XDG_STATE_HOME/lmcfg (else ~/.local/state/lmcfg) before the first change, written back "
      "and\n"
      "read back; an interrupted run is finished from that record by running it again.\n"
      "Before the first write the layers, curves and command table it changes are saved as an\n"
      "undo record (lmcfg undo --list; lmcfg undo puts them back) unless --no-undo.\n"
      "Ctrl-C stops between two telegrams (exit 130) and names the step.");
  add_link_options(sub, o->common);
  add_output_options(sub, o->common);
  sub->add_option("--layers", o->layers, "layers to default: os,mc,intf,appl");
  sub->add_flag("--curves", o->curves, "delete all curves (and save to flash)");
  sub->add_flag("--ct", o->ct, "delete all command table entries (and save to flash)");
  sub->add_flag(
      "--include-comm", o->include_comm,
      "also default communication parameters (the drive may stop answering on these settings)");
  sub->add_flag("--yes,-y", o->yes, "do not ask for confirmation");
  sub->add_flag("--no-undo", o->no_undo,
                "do not save the drive's previous values as an undo record before writing "
                "(lmcfg undo)");
  add_audit_options(sub, o->audit);
  sub->callback([o, &exit_code] { exit_code = run(*o); });
}
}  // namespace lmcfg::cli
