// lmcfg default: set chosen layers to factory defaults, optionally delete curves and the command
// table.
#include <unistd.h>

#include <cstdio>
#include <iostream>

#include "command.hpp"
#include "link_options.hpp"
#include "ops/factory_reset.hpp"

namespace lmcfg::cli {
namespace {

struct DefaultCli {
  CommonOptions common;
  std::string layers;
  bool curves = false;
  bool ct = false;
  bool include_comm = false;
  bool yes = false;
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
  if (!o.yes) {
    if (!::isatty(STDIN_FILENO)) {
      return fail("default",
                  Error(Errc::invalid_argument,
                        "refusing to default a drive without --yes when stdin is not a terminal"));
    }
    std::fprintf(stderr, "Set %s%s%s of drive %s on %s to factory defaults? [y/N] ",
                 o.layers.empty() ? "" : ("layers " + o.layers).c_str(),
                 o.curves ? ", delete all curves" : "", o.ct ? ", delete the command table" : "",
                 o.common.id.c_str(), o.common.port.c_str());
    std::string answer;
    std::getline(std::cin, answer);
    if (answer != "y" && answer != "Y" && answer != "yes") {
      std::fprintf(stderr, "cancelled; nothing written\n");
      return kOk;
    }
  }
  std::optional<db::Database> holder;
  const db::Database* db = load_database(o.common, holder);
  auto session = open_link(o.common);
  if (!session.ok()) return fail("default", session.error());
  d.progress = make_progress(o.common);
  auto rep = ops::default_drive((*session)->client(), d, db);
  end_progress(o.common);
  auto closed = (*session)->close();
  if (!rep.ok()) return fail("default", rep.error());
  if (!closed.ok()) return fail("default", closed.error());
  if (!o.common.quiet) {
    for (const auto& s : rep->done) std::fprintf(stderr, "done: %s\n", s.c_str());
    if (rep->link_may_change)
      std::fprintf(stderr,
                   "note: communication parameters are at their factory defaults: the drive now "
                   "takes its MACID "
                   "and baud rate from its hex switches S2 and S1 (seed 003 §3.2)\n");
  }
  return kOk;
}

const Register reg(40, [](CLI::App& app, int& exit_code) {
  auto o = std::make_shared<DefaultCli>();
  auto* sub = app.add_subcommand(
      "default", "Set layers to factory defaults; optionally delete curves and command table");
  sub->footer(
      "Examples:\n"
      "  lmcfg default --port /dev/ttyUSB0 --layers mc,appl --yes\n"
      "  lmcfg default --port /dev/ttyUSB0 --layers os,mc,intf,appl --curves --ct\n"
      "Stops MC, defaults, deletes and saves to flash as asked, starts MC and resets. The drive's\n"
      "communication parameters are kept unless --include-comm.");
  add_link_options(sub, o->common);
  add_output_options(sub, o->common);
  sub->add_option("--layers", o->layers, "layers to default: os,mc,intf,appl");
  sub->add_flag("--curves", o->curves, "delete all curves (and save to flash)");
  sub->add_flag("--ct", o->ct, "delete all command table entries (and save to flash)");
  sub->add_flag(
      "--include-comm", o->include_comm,
      "also default communication parameters (the drive may stop answering on these settings)");
  sub->add_flag("--yes,-y", o->yes, "do not ask for confirmation");
  sub->callback([o, &exit_code] { exit_code = run(*o); });
});

}  // namespace
}  // namespace lmcfg::cli
