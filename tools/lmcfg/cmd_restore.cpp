// lmcfg restore FILE: plan (checks, no writes), execute, verify.
#include <cstdio>
#include <nlohmann/json.hpp>

#include "command.hpp"
#include "config/config_io.hpp"
#include "link_options.hpp"
#include "ops/restore.hpp"

namespace lmcfg::cli {
namespace {

struct RestoreCli {
  CommonOptions common;
  std::string file;
  bool dry_run = false;
  bool no_default = false;
  bool include_comm = false;
  bool no_reset = false;
  ReconnectOptions reconnect;
};

void report_json(const ops::Plan& plan, const char* outcome,
                 const std::vector<std::string>& mismatches, const std::string& error,
                 const std::optional<ops::RelinkReport>& relink = {}) {
  nlohmann::ordered_json j;
  j["outcome"] = outcome;
  if (relink)
    j["link_after"] = {
        {"changed", relink->changed}, {"summary", relink->summary}, {"reasons", relink->reasons}};
  j["problems"] = plan.problems;
  nlohmann::ordered_json steps = nlohmann::ordered_json::array();
  for (const auto& s : plan.steps) steps.push_back(s.text);
  j["steps"] = steps;
  j["skipped"] = plan.skipped;
  j["notes"] = plan.notes;
  j["mismatches"] = mismatches;
  if (!error.empty()) j["error"] = error;
  std::printf("%s\n", j.dump(2).c_str());
}

int run(RestoreCli& o) {
  // The file first: a bad file never opens the link, so nothing is written.
  auto file = config::read_config_file(o.file);
  if (!file.ok()) return fail("restore", file.error());
  std::optional<db::Database> holder;
  const db::Database* db = load_database(o.common, holder);
  auto overrides = relink_overrides(o.reconnect);
  if (!overrides.ok()) return fail("restore", overrides.error());
  auto session = open_link(o.common);
  if (!session.ok()) return fail("restore", session.error());
  auto& client = (*session)->client();
  ops::RestoreOptions ro;
  ro.default_first = !o.no_default;
  ro.include_comm = o.include_comm;
  ro.reset_after = !o.no_reset;
  ro.progress = make_progress(o.common);
  auto finish = [&](int code) {
    end_progress(o.common);
    if (auto c = (*session)->close(); !c.ok()) return fail("restore", c.error());
    return code;
  };

  auto plan = ops::plan_restore(client, *file, db, ro);
  if (!plan.ok()) return finish(fail("restore", plan.error()));
  if (!plan->ok()) {
    if (o.common.json)
      report_json(*plan, "plan refused", {}, "");
    else
      std::fputs(ops::render_plan(*plan).c_str(), stderr);
    return finish(kPlanRefused);
  }
  if (o.dry_run) {
    if (o.common.json)
      report_json(*plan, "dry run", {}, "");
    else
      std::fputs(ops::render_plan(*plan).c_str(), stdout);
    return finish(kOk);
  }
  if (!o.common.quiet && !o.common.json) {
    for (const auto& s : plan->skipped) std::fprintf(stderr, "skip: %s\n", s.c_str());
  }
  if (auto r = ops::execute_plan(client, *plan, ro); !r.ok()) {
    if (o.common.json) report_json(*plan, "failed", {}, r.error().message);
    return finish(fail("restore", r.error()));
  }
  std::optional<ops::RelinkReport> relink;
  // Without the reset the restored link settings act at the next start-up only.
  if (plan->link_may_change && o.no_reset && !o.common.quiet && !o.common.json)
    std::fprintf(stderr,
                 "restore: the restored communication parameters act after the next restart\n");
  if (plan->link_may_change && !o.no_reset) {
    auto r = ops::reconnect(**session, ops::expected_link(*plan, db), *overrides);
    if (!r.ok()) {
      return finish(fail(
          "restore", Error(r.error().code,
                           "written, but the drive could not be found again: " + r.error().message +
                               ". Give its settings with --reconnect-baud/-id/-checksum, "
                               "or reconnect and run 'lmcfg diff FILE drive' to verify")));
    }
    relink = std::move(r).value();
    if (relink->changed && !o.common.quiet && !o.common.json) {
      std::fprintf(stderr,
                   "restore: the restored link settings are active: %s; use them from now on\n",
                   relink->summary.c_str());
    }
  }
  auto verify = ops::verify_restore(client, *plan, ro);
  if (!verify.ok()) {
    return finish(fail(
        "restore",
        Error(verify.error().code, "written, but verification could not read the drive back: " +
                                       verify.error().message)));
  }
  if (!verify->ok()) {
    if (o.common.json) {
      report_json(*plan, "verify mismatch", verify->mismatches, "", relink);
    } else {
      std::fprintf(stderr, "lmcfg restore: verification found %zu mismatch(es):\n",
                   verify->mismatches.size());
      for (const auto& m : verify->mismatches) std::fprintf(stderr, "  %s\n", m.c_str());
    }
    return finish(kVerifyMismatch);
  }
  if (o.common.json) {
    report_json(*plan, "restored and verified", {}, "", relink);
  } else if (!o.common.quiet) {
    std::fprintf(stderr,
                 "restore: %zu step(s) done, verified: the drive matches %s (%llu telegrams)\n",
                 plan->steps.size(), o.file.c_str(),
                 static_cast<unsigned long long>(client.stats().requests));
  }
  return finish(kOk);
}

const Register reg(30, [](CLI::App& app, int& exit_code) {
  auto o = std::make_shared<RestoreCli>();
  auto* sub = app.add_subcommand("restore",
                                 "Restore a configuration file onto a drive: plan, write, verify");
  sub->footer(
      "Examples:\n"
      "  lmcfg restore axis1.json --port /dev/ttyUSB0 --id 0x11 --dry-run\n"
      "  lmcfg restore axis1.json --port /dev/ttyUSB0 --id 0x11\n"
      "The plan checks every item against the drive and the database before any write; any "
      "problem\n"
      "refuses the restore (exit 3, nothing written). After writing, the drive is read back (exit "
      "6 on\n"
      "a mismatch). An interrupted restore can be run again and converges.");
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
  sub->add_flag("--no-reset", o->no_reset,
                "do not reset the drive at the end (ROM values act after the next restart)");
  sub->callback([o, &exit_code] { exit_code = run(*o); });
});

}  // namespace
}  // namespace lmcfg::cli
