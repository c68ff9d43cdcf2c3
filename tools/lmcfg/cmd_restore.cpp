// lmcfg restore FILE: plan (checks, no writes), execute, verify.
#include <cstdio>
#include <nlohmann/json.hpp>

#include "command.hpp"
#include "config/config_io.hpp"
#include "link_options.hpp"
#include "ops/interrupt.hpp"
#include "ops/recovery.hpp"
#include "ops/restore_run.hpp"

namespace lmcfg::cli {
namespace {

struct RestoreCli {
  CommonOptions common;
  std::string file;
  bool dry_run = false;
  bool no_default = false;
  bool include_comm = false;
  bool no_reset = false;
  bool yes = false;
  ReconnectOptions reconnect;
};

void report_json(const ops::RestoreOutcome& out, const std::string& file) {
  nlohmann::ordered_json j;
  j["file"] = file;
  j["outcome"] = ops::stage_name(out.stage);
  if (out.relink)
    j["link_after"] = {{"changed", out.relink->changed},
                       {"summary", out.relink->summary},
                       {"reasons", out.relink->reasons}};
  const auto plan = ops::plan_json(out.plan);  // alive while its items are copied
  for (const auto& [k, v] : plan.items()) j[k] = v;
  j["mismatches"] = out.mismatches;
  if (out.error) j["error"] = out.error->message;
  std::printf("%s\n", j.dump(2).c_str());
}

int run(RestoreCli& o) {
  // From the start: a signal before the link opens stops the plan before its
  // first telegram, with the message and exit 130, instead of killing silently.
  ops::install_interrupt_handlers();
  using S = ops::RestoreOutcome::Stage;
  // The file first: a bad file never opens the link, so nothing is written.
  auto file = config::read_config_file(o.file);
  if (!file.ok()) return fail("restore", file.error());
  const db::Database db = load_database(o.common);
  auto overrides = relink_overrides(o.reconnect);
  if (!overrides.ok()) return fail("restore", overrides.error());
  auto session = open_link(o.common);
  if (!session.ok()) return fail("restore", session.error());
  auto& client = (*session)->client();
  auto copt = client.options();
  copt.cancel = &ops::interrupt_flag();
  client.set_options(copt);

  ops::RestoreRunOptions ro;
  auto record = ops::recovery_path("restore", o.common.port, copt.id);
  if (!record.ok()) return fail("restore", record.error());
  ro.restore.recovery_path = *record;
  ro.restore.port = o.common.port;
  ro.restore.default_first = !o.no_default;
  ro.restore.include_comm = o.include_comm;
  ro.restore.reset_after = !o.no_reset;
  ro.restore.progress = make_progress(o.common);
  ro.dry_run = o.dry_run;
  ro.overrides = *overrides;
  ro.confirm = [&](const ops::Plan& plan) {
    end_progress(o.common);
    // The plan goes to stderr when stdout carries the JSON report.
    if (!o.yes) std::fputs(ops::render_plan(plan).c_str(), o.common.json ? stderr : stdout);
    std::fflush(stdout);
    return ops::confirm("Write this plan to drive " + o.common.id + " on " + o.common.port + "?",
                        "restore " + o.file + " onto a drive", o.yes);
  };
  auto out = ops::run_restore(**session, *file, db, ro);
  end_progress(o.common);
  const bool text = !o.common.json;
  if (o.common.json) report_json(out, o.file);
  int code = kOk;
  switch (out.stage) {
    case S::failed:
      code = exit_code_for(*out.error);
      std::fprintf(stderr, "lmcfg restore: %s\n", out.error->message.c_str());
      break;
    case S::plan_refused:
      if (text) std::fputs(ops::render_plan(out.plan).c_str(), stderr);
      code = kPlanRefused;
      break;
    case S::dry_run:
      if (text) std::fputs(ops::render_plan(out.plan).c_str(), stdout);
      break;
    case S::declined:
      std::fprintf(stderr, "cancelled; nothing written\n");
      break;
    case S::nothing_to_do:
      if (text && !o.common.quiet) {
        for (const auto& s : out.plan.skipped) std::fprintf(stderr, "skip: %s\n", s.c_str());
        std::printf("nothing to do: the drive already matches %s\n", o.file.c_str());
      }
      break;
    case S::verify_mismatch:
      if (text) {
        std::fprintf(stderr, "lmcfg restore: verification found %zu mismatch(es):\n",
                     out.mismatches.size());
        for (const auto& m : out.mismatches) std::fprintf(stderr, "  %s\n", m.c_str());
      }
      code = kVerifyMismatch;
      break;
    case S::restored:
      if (text && !o.common.quiet) {
        if (out.plan.link_may_change && o.no_reset)
          std::fprintf(stderr,
                       "restore: the restored communication parameters act after the next "
                       "restart\n");
        if (out.relink && out.relink->changed)
          std::fprintf(stderr,
                       "restore: the restored link settings are active: %s; use them from now "
                       "on\n",
                       out.relink->summary.c_str());
        std::fprintf(stderr,
                     "restore: %zu step(s) done, verified: the drive matches %s (%llu "
                     "telegrams)\n",
                     out.plan.steps.size(), o.file.c_str(),
                     static_cast<unsigned long long>(client.stats().requests));
      }
      break;
  }
  if (auto c = (*session)->close(); !c.ok()) return fail("restore", c.error());
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
  add_output_options(sub, o->common);
  sub->add_flag("--dry-run", o->dry_run, "print the plan and exit without writing");
  sub->add_flag(
      "--no-default", o->no_default,
      "write only differences and set leftovers to defaults, instead of defaulting layers first");
  sub->add_flag("--include-comm", o->include_comm,
                "also restore communication parameters (baud rate, MACID); after the reset the "
                "tool finds the drive "
                "with the settings they select");
  add_reconnect_options(sub, o->reconnect);
  sub->add_flag("--yes,-y", o->yes,
                "do not ask for confirmation (needed when stdin is not a terminal)");
  sub->add_flag("--no-reset", o->no_reset,
                "do not reset the drive at the end (ROM values act after the next restart)");
  sub->callback([o, &exit_code] { exit_code = run(*o); });
}
}  // namespace lmcfg::cli
