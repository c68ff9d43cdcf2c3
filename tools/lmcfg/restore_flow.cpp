// The restore flow of `lmcfg restore`, `lmcfg undo` and `lmcfg fleet restore`,
// for LinRS drives and DeviceNet controllers alike: the library runs the
// protocol's plan, execute and verify; confirmation, the text or JSON report,
// the journal record and the exit code are this file's, once for both.
#include "restore_flow.hpp"

#include <cstdio>
#include <nlohmann/json.hpp>

#include "command.hpp"
#include "common/families.hpp"
#include "confirm.hpp"
#include "ops/devicenet_restore.hpp"
#include "ops/interrupt.hpp"
#include "ops/recovery.hpp"
#include "report/json_reports.hpp"

namespace lmcfg::cli {
namespace {

// The plan for people and as items, of whichever protocol ran.
std::string plan_text(const ops::RestoreOutcome& out, const std::string& file_name) {
  return out.devicenet ? ops::render_devicenet_plan(*out.devicenet, file_name)
                       : ops::render_plan(out.plan);
}

// The documented exit code of an outcome (README "Exit codes").
int exit_code_of(const ops::RestoreOutcome& out) {
  using S = ops::RestoreOutcome::Stage;
  switch (out.stage) {
    case S::failed:
      return exit_code_for(*out.error);
    case S::plan_refused:
      return kPlanRefused;
    case S::verify_mismatch:
      return kVerifyMismatch;
    case S::nothing_to_do:
    case S::restored:
      return out.skipped_any() ? kRestoredExcept : kOk;
    case S::dry_run:
    case S::declined:
      return kOk;
  }
  return kOk;
}

void print_nothing_to_do(const ops::RestoreOutcome& out, const std::string& file_name,
                         const CommonOptions& common) {
  if (out.devicenet) {
    if (!common.quiet)
      std::printf("%snothing to do: the controller already matches %s\n",
                  plan_text(out, file_name).c_str(), file_name.c_str());
    return;
  }
  if (!common.quiet) {
    for (const auto& s : out.plan.skipped) std::fprintf(stderr, "skip: %s\n", s.c_str());
    std::printf("nothing to do: the drive already matches %s%s\n", file_name.c_str(),
                out.skipped_any() ? " except the skipped values" : "");
  }
  std::fputs(ops::render_skipped_incompatible(out.plan).c_str(), stdout);
}

// LinRS: what the run did beside the steps, and the summary. A DeviceNet
// restore's summary is its caller's, once the connection is released.
void print_restored(const ops::RestoreOutcome& out, const std::string& file_name,
                    const CommonOptions& common, const RestoreFlags& f,
                    unsigned long long telegrams) {
  if (out.devicenet) return;
  if (!common.quiet) {
    if (out.plan.link_may_change && f.no_reset)
      std::fprintf(stderr,
                   "restore: the restored communication parameters act after the next restart\n");
    if (out.relink && out.relink->changed)
      std::fprintf(stderr,
                   "restore: the restored link settings are active: %s; use them from now on\n",
                   out.relink->summary.c_str());
    if (out.second_pass)
      std::fprintf(stderr,
                   "restore: after the restart a table differed from the file (its flash held "
                   "another one): second pass, %zu step(s) (write, save to flash, start MC)\n",
                   out.second_pass->steps.size());
    // docs/field.md "Slow saves": the read-back decided these steps.
    for (const auto& u : out.unacknowledged)
      std::fprintf(stderr, "restore: note: %s; the read-back matched the file\n", u.c_str());
    std::fprintf(stderr,
                 "restore: %zu step(s) done, verified: the drive matches %s%s (%llu telegrams)\n",
                 out.plan.steps.size(), file_name.c_str(),
                 out.skipped_any() ? " except the skipped values" : "", telegrams);
  }
  std::fputs(ops::render_skipped_incompatible(out.plan).c_str(), stdout);
}

// The outcome for people (without --json; an error also with it).
void print_outcome(const ops::RestoreOutcome& out, const std::string& file_name,
                   const CommonOptions& common, const RestoreFlags& f,
                   unsigned long long telegrams) {
  using S = ops::RestoreOutcome::Stage;
  const bool text = !common.json;
  switch (out.stage) {
    case S::failed:
      std::fprintf(stderr, "lmcfg restore: %s%s\n",
                   out.devicenet && out.written ? "the controller is partially restored: " : "",
                   out.error->message.c_str());
      break;
    case S::plan_refused:
      if (text) std::fputs(plan_text(out, file_name).c_str(), stderr);
      break;
    case S::dry_run:
      if (!text) break;
      std::fputs(plan_text(out, file_name).c_str(), stdout);
      if (out.devicenet && out.devicenet->writes.empty() && !common.quiet)
        std::printf("nothing to do: the controller already matches %s\n", file_name.c_str());
      break;
    case S::declined:
      std::fprintf(stderr, "cancelled; nothing written\n");
      break;
    case S::nothing_to_do:
      if (text) print_nothing_to_do(out, file_name, common);
      break;
    case S::verify_mismatch:
      if (!text) break;
      std::fprintf(stderr, "lmcfg restore: verification found %zu mismatch(es)%s:\n",
                   out.mismatches.size(),
                   out.second_pass ? " after a second pass that wrote the tables again" : "");
      for (const auto& m : out.mismatches) std::fprintf(stderr, "  %s\n", m.c_str());
      for (const auto& u : out.unacknowledged)
        std::fprintf(stderr, "restore: note: %s\n", u.c_str());
      break;
    case S::restored:
      if (text) print_restored(out, file_name, common, f, telegrams);
      break;
  }
}

void record_restore(const ops::RestoreOutcome& out, int code, const RestoreTarget& t,
                    const std::string& file_name, const CommonOptions& common,
                    const RestoreFlags& f) {
  ops::JournalEntry e;
  e.audit = audit_of(f.audit);
  e.command = f.undo_name;
  e.port = common.port;
  e.macid = t.macid;
  e.position = f.position;
  e.file = file_name;
  e.steps = report::restore_steps_json(out);
  e.outcome = ops::outcome_name(out);
  e.exit_code = code;
  if (out.error) e.error = out.error->message;
  for (const auto& m : out.mismatches) e.error += (e.error.empty() ? "" : "; ") + m;
  if (out.undo) e.undo = out.undo->path.string();
  record_in_journal(f.undo_name == "fleet-restore" ? "fleet restore" : f.undo_name.c_str(),
                    std::move(e));
}

// The LinRS run's options: the recovery record, the restore flags, the undo
// record (none for a dry run).
Result<ops::RestoreRunOptions> linrs_run_options(const CommonOptions& common, const RestoreFlags& f,
                                                 const link::RelinkOverrides& overrides,
                                                 std::uint8_t id, ProgressBar& bar) {
  ops::RestoreRunOptions ro;
  LMCFG_ASSIGN_OR_RETURN(ro.restore.recovery_path, ops::recovery_path("restore", common.port, id));
  ro.restore.port = common.port;
  ro.restore.default_first = !f.no_default;
  ro.restore.include_comm = f.include_comm;
  ro.restore.reset_after = !f.no_reset;
  ro.restore.skip_incompatible = f.skip_incompatible;
  LMCFG_ASSIGN_OR_RETURN(ro.restore.family, families::parse(f.family, "--family"));
  ro.restore.progress = bar.callback();
  ro.dry_run = f.dry_run;
  ro.overrides = overrides;
  if (!f.no_undo && !f.dry_run) {
    LMCFG_ASSIGN_OR_RETURN(const auto dir, ops::undo_dir());
    ro.undo = ops::UndoOptions{true, dir, common.port, id, f.undo_name, ops::kUndoKeep};
  }
  return ro;
}

}  // namespace

void print_undo_saved(const ops::UndoSaved& u, const CommonOptions& common) {
  if (common.quiet || common.json) return;
  std::fprintf(stderr, "undo: saved the target's previous values to %s; to put them back: %s\n",
               u.path.string().c_str(), u.command.c_str());
}

void add_restore_flags(CLI::App* sub, RestoreFlags& f) {
  sub->add_flag("--dry-run", f.dry_run, "print the plan and exit without writing");
  sub->add_flag(
      "--no-default", f.no_default,
      "write only differences and set leftovers to defaults, instead of defaulting layers first");
  sub->add_flag("--include-comm", f.include_comm,
                "also restore communication parameters (baud rate, MACID); after the reset the "
                "tool finds the drive "
                "with the settings they select");
  add_reconnect_options(sub, f.reconnect);
  sub->add_flag("--yes,-y", f.yes,
                "do not ask for confirmation (needed when stdin is not a terminal)");
  sub->add_flag("--no-reset", f.no_reset,
                "do not reset the drive at the end (ROM values act after the next restart)");
  sub->add_flag("--skip-incompatible", f.skip_incompatible,
                "restore what the target can take and list the values it cannot (UPID absent, "
                "type, range, read-only, curve/command table limits); exit 7 when any was "
                "skipped");
  sub->add_option("--family", f.family,
                  "the target's drive family: E1100 (default), B1100, C1100, E1200, E1400 "
                  "(docs/families.md)");
  sub->add_flag("--no-undo", f.no_undo,
                "do not save the target's previous values as an undo record before writing "
                "(lmcfg undo)");
  add_audit_options(sub, f.audit);
}

Result<ops::Consent> confirm_restore(const std::string& plan, const RestoreTarget& t,
                                     const std::string& file_name, const CommonOptions& common,
                                     const RestoreFlags& f) {
  if (t.bar) t.bar->end();
  // The plan goes to stderr when stdout carries the JSON report.
  if (!f.yes || (t.plan_with_yes && !common.quiet && !common.json))
    std::fputs(plan.c_str(), common.json ? stderr : stdout);
  std::fflush(stdout);
  return confirm(t.question, "restore " + file_name + " onto a " + t.noun, f.yes);
}

int finish_restore(const ops::RestoreOutcome& out, const RestoreTarget& t,
                   const std::string& file_name, const CommonOptions& common,
                   const RestoreFlags& f) {
  if (t.bar) t.bar->end();
  if (common.json) std::printf("%s\n", report::restore_json(out, file_name).dump(2).c_str());
  if (out.undo) print_undo_saved(*out.undo, common);
  print_outcome(out, file_name, common, f, t.telegrams ? t.telegrams() : 0);
  const int code = exit_code_of(out);
  if (out.written) record_restore(out, code, t, file_name, common, f);
  return code;
}

int restore_on_session(link::Session& session, const config::DriveConfig& file,
                       const std::string& file_name, const CommonOptions& common,
                       const RestoreFlags& f, const link::RelinkOverrides& overrides,
                       const db::Database& db, ops::RestoreOutcome& out) {
  // The session was opened with the interrupt flag (open_link, line_links):
  // SIGINT/SIGTERM let the telegram in flight complete.
  auto& client = session.client();
  const std::uint8_t id = client.options().id;
  ProgressBar bar(common);
  auto ro = linrs_run_options(common, f, overrides, id, bar);
  if (!ro.ok()) return fail("restore", ro.error());
  RestoreTarget t;
  t.bar = &bar;
  t.noun = "drive";
  t.question = "Write this plan to drive " + common.id + " on " + common.port + "?";
  t.macid = id;
  t.telegrams = [&client] { return static_cast<unsigned long long>(client.stats().requests); };
  ro->confirm = [&](const ops::Plan& plan) {
    return confirm_restore(ops::render_plan(plan), t, file_name, common, f);
  };
  out = ops::run_restore(session, file, db, *ro);
  return finish_restore(out, t, file_name, common, f);
}

}  // namespace lmcfg::cli
