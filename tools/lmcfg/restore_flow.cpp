// The restore flow of `lmcfg restore` and `lmcfg fleet restore`.
#include "restore_flow.hpp"

#include <cstdio>
#include <nlohmann/json.hpp>

#include "command.hpp"
#include "confirm.hpp"
#include "ops/interrupt.hpp"
#include "ops/recovery.hpp"

namespace lmcfg::cli {
namespace {

void report_json(const ops::RestoreOutcome& out, const std::string& file) {
  nlohmann::ordered_json j;
  j["file"] = file;
  j["outcome"] = ops::outcome_name(out);
  if (out.relink)
    j["link_after"] = {{"changed", out.relink->changed},
                       {"summary", out.relink->summary},
                       {"reasons", out.relink->reasons}};
  const auto plan = ops::plan_json(out.plan);  // alive while its items are copied
  for (const auto& [k, v] : plan.items()) j[k] = v;
  if (out.second_pass) j["second_pass"] = ops::plan_json(*out.second_pass)["steps"];
  j["mismatches"] = out.mismatches;
  if (out.undo) j["undo"] = undo_json(*out.undo);
  if (out.error) j["error"] = out.error->message;
  std::printf("%s\n", j.dump(2).c_str());
}

}  // namespace

void print_undo_saved(const ops::UndoSaved& u, const CommonOptions& common) {
  if (common.quiet || common.json) return;
  std::fprintf(stderr, "undo: saved the target's previous values to %s; to put them back: %s\n",
               u.path.c_str(), u.command.c_str());
}

nlohmann::ordered_json undo_json(const ops::UndoSaved& u) {
  return {{"path", u.path.string()}, {"command", u.command}};
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
  sub->add_flag("--no-undo", f.no_undo,
                "do not save the target's previous values as an undo record before writing "
                "(lmcfg undo)");
  add_audit_options(sub, f.audit);
}

int restore_on_session(ops::Session& session, const config::DriveConfig& file,
                       const std::string& file_name, const CommonOptions& common,
                       const RestoreFlags& f, const ops::RelinkOverrides& overrides,
                       const db::Database& db, ops::RestoreOutcome& out) {
  using S = ops::RestoreOutcome::Stage;
  auto& client = session.client();
  auto copt = client.options();
  copt.cancel = &ops::interrupt_flag();
  client.set_options(copt);

  ops::RestoreRunOptions ro;
  auto record = ops::recovery_path("restore", common.port, copt.id);
  if (!record.ok()) return fail("restore", record.error());
  ro.restore.recovery_path = *record;
  ro.restore.port = common.port;
  ro.restore.default_first = !f.no_default;
  ro.restore.include_comm = f.include_comm;
  ro.restore.reset_after = !f.no_reset;
  ro.restore.skip_incompatible = f.skip_incompatible;
  ro.restore.progress = make_progress(common);
  ro.dry_run = f.dry_run;
  ro.overrides = overrides;
  if (!f.no_undo && !f.dry_run) {
    auto dir = ops::undo_dir();
    if (!dir.ok()) return fail("restore", dir.error());
    ro.undo = ops::UndoOptions{true, *dir, common.port, copt.id, f.undo_name, ops::kUndoKeep};
  }
  ro.confirm = [&](const ops::Plan& plan) {
    end_progress(common);
    // The plan goes to stderr when stdout carries the JSON report.
    if (!f.yes) std::fputs(ops::render_plan(plan).c_str(), common.json ? stderr : stdout);
    std::fflush(stdout);
    return confirm("Write this plan to drive " + common.id + " on " + common.port + "?",
                   "restore " + file_name + " onto a drive", f.yes);
  };
  out = ops::run_restore(session, file, db, ro);
  end_progress(common);
  const bool text = !common.json;
  if (common.json) report_json(out, file_name);
  if (out.undo) print_undo_saved(*out.undo, common);
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
      if (text && !common.quiet) {
        for (const auto& s : out.plan.skipped) std::fprintf(stderr, "skip: %s\n", s.c_str());
        if (out.skipped_any())
          std::printf("nothing to do: the drive already matches %s except the skipped values\n",
                      file_name.c_str());
        else
          std::printf("nothing to do: the drive already matches %s\n", file_name.c_str());
      }
      if (text) std::fputs(ops::render_skipped_incompatible(out.plan).c_str(), stdout);
      if (out.skipped_any()) code = kRestoredExcept;
      break;
    case S::verify_mismatch:
      if (text) {
        std::fprintf(stderr, "lmcfg restore: verification found %zu mismatch(es)%s:\n",
                     out.mismatches.size(),
                     out.second_pass ? " after a second pass that wrote the tables again" : "");
        for (const auto& m : out.mismatches) std::fprintf(stderr, "  %s\n", m.c_str());
      }
      code = kVerifyMismatch;
      break;
    case S::restored:
      if (text && !common.quiet) {
        if (out.plan.link_may_change && f.no_reset)
          std::fprintf(stderr,
                       "restore: the restored communication parameters act after the next "
                       "restart\n");
        if (out.relink && out.relink->changed)
          std::fprintf(stderr,
                       "restore: the restored link settings are active: %s; use them from now "
                       "on\n",
                       out.relink->summary.c_str());
        if (out.second_pass)
          std::fprintf(stderr,
                       "restore: after the restart a table differed from the file (its flash "
                       "held another one): second pass, %zu step(s) (write, save to flash, start "
                       "MC)\n",
                       out.second_pass->steps.size());
        std::fprintf(stderr,
                     "restore: %zu step(s) done, verified: the drive matches %s%s (%llu "
                     "telegrams)\n",
                     out.plan.steps.size(), file_name.c_str(),
                     out.skipped_any() ? " except the skipped values" : "",
                     static_cast<unsigned long long>(client.stats().requests));
      }
      if (text) std::fputs(ops::render_skipped_incompatible(out.plan).c_str(), stdout);
      if (out.skipped_any()) code = kRestoredExcept;
      break;
  }
  if (out.written) {
    ops::JournalEntry e;
    e.audit = audit_of(f.audit);
    e.command = f.undo_name;
    e.port = common.port;
    e.macid = copt.id;
    e.position = f.position;
    e.file = file_name;
    e.steps = ops::plan_json(out.plan)["steps"];
    if (out.second_pass) {
      // A named value: a range-for over a member of a temporary would read freed memory.
      const auto second = ops::plan_json(*out.second_pass);
      for (const auto& s : second["steps"]) e.steps.push_back(s);
    }
    e.outcome = ops::outcome_name(out);
    e.exit_code = code;
    if (out.error) e.error = out.error->message;
    for (const auto& m : out.mismatches) e.error += (e.error.empty() ? "" : "; ") + m;
    if (out.undo) e.undo = out.undo->path.string();
    record_in_journal(f.undo_name == "fleet-restore" ? "fleet restore" : f.undo_name.c_str(),
                      std::move(e));
  }
  return code;
}

}  // namespace lmcfg::cli
