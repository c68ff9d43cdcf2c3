#include "ops/restore_run.hpp"

#include "ops/expected_link.hpp"
#include "ops/recovery.hpp"

namespace lmcfg::ops {

namespace {

// The target's values in the file's scope, from the plan's reads, saved
// before the first write; any failure refuses the restore with nothing written.
Result<UndoSaved> save_restore_undo(client::Client& c, const Plan& plan, const config::Scope& scope,
                                    const db::Database& db, const UndoOptions& undo) {
  auto cfg = undo_config_from_plan(c, plan, scope, db);
  if (!cfg.ok()) {
    Error e = std::move(cfg).error();
    e.message =
        "reading the target's curves for the undo record: " + e.message + "; nothing written";
    return e;
  }
  return save_undo(undo, *cfg, db);
}

}  // namespace

const char* stage_name(RestoreOutcome::Stage s) {
  using S = RestoreOutcome::Stage;
  switch (s) {
    case S::failed:
      return "failed";
    case S::plan_refused:
      return "plan refused";
    case S::dry_run:
      return "dry run";
    case S::declined:
      return "declined";
    case S::nothing_to_do:
      return "nothing to do";
    case S::verify_mismatch:
      return "verify mismatch";
    case S::restored:
      return "restored and verified";
  }
  return "?";
}

std::string outcome_name(const RestoreOutcome& out) {
  using S = RestoreOutcome::Stage;
  if (out.skipped_any() && out.stage == S::restored)
    return "restored except the listed values, verified";
  if (out.skipped_any() && out.stage == S::nothing_to_do)
    return "nothing to do except the listed values";
  return stage_name(out.stage);
}

std::optional<Error> outcome_error(const RestoreOutcome& out) {
  using S = RestoreOutcome::Stage;
  if (out.stage == S::failed && out.error) return out.error;
  auto joined = [](const std::vector<std::string>& items) {
    std::string all;
    for (const auto& i : items) all += (all.empty() ? "" : "; ") + i;
    return all;
  };
  if (out.stage == S::plan_refused)
    return Error(Errc::plan_refused,
                 "restore refused: " + joined(out.plan.problems) + "; nothing written");
  if (out.stage == S::verify_mismatch)
    return Error(Errc::verify_mismatch,
                 "written, but the drive reads back differently: " + joined(out.mismatches));
  return std::nullopt;
}

RestoreOutcome run_restore(link::Session& session, const config::DriveConfig& file,
                           const db::Database& db, const RestoreRunOptions& o) {
  using S = RestoreOutcome::Stage;
  RestoreOutcome out;
  auto& client = session.client();
  auto fail = [&](Error e) {
    out.stage = S::failed;
    out.error = std::move(e);
    return std::move(out);
  };
  auto plan = plan_restore(client, file, db, o.restore);
  if (!plan.ok()) {
    Error e = std::move(plan).error();
    if (e.code == make_error_code(Errc::interrupted))
      e.message = "interrupted while planning (reads only): " + e.message + "; nothing written";
    return fail(std::move(e));
  }
  out.plan = std::move(plan).value();
  if (!out.plan.ok()) {
    out.stage = S::plan_refused;
    return out;
  }
  if (o.dry_run) {
    out.stage = S::dry_run;
    return out;
  }
  // The plan compared every item with the target: its reads are the verification.
  if (out.plan.nothing_to_do()) {
    out.stage = S::nothing_to_do;
    return out;
  }
  if (o.confirm) {
    auto consent = o.confirm(out.plan);
    if (!consent.ok()) return fail(std::move(consent).error());
    if (*consent == Consent::declined) {
      out.stage = S::declined;
      return out;
    }
  }
  if (o.undo.enabled) {
    auto saved = save_restore_undo(client, out.plan, file.scope, db, o.undo);
    if (!saved.ok()) return fail(std::move(saved).error());
    out.undo = std::move(saved).value();
  }
  out.written = true;
  if (auto r = execute_plan(client, out.plan, o.restore, &out.unacknowledged); !r.ok())
    return fail(std::move(r).error());
  if (out.plan.link_may_change && o.restore.reset_after) {
    auto r = link::reconnect_within(session, expected_link(out.plan, db), o.overrides,
                                    client.options().recover_timeout);
    if (!r.ok()) {
      return fail(Error(r.error().code,
                        "written, but the drive could not be found again: " + r.error().message +
                            ". Give its settings with --reconnect-baud/-id/-checksum, "
                            "or reconnect and run 'lmcfg diff FILE drive' to verify"));
    }
    out.relink = std::move(r).value();
  }
  auto verify = verify_restore(client, out.plan, o.restore);
  if (!verify.ok()) {
    return fail(Error(
        verify.error().code,
        "written, but verification could not read the drive back: " + verify.error().message));
  }
  if (verify->ct_differs || verify->curves_differ) {
    auto pass = plan_table_pass(client, out.plan, *verify, o.restore);
    if (!pass.ok()) {
      return fail(Error(pass.error().code,
                        "written, but reading the tables for a second pass "
                        "failed: " +
                            pass.error().message));
    }
    if (!pass->steps.empty()) {
      out.second_pass = std::move(pass).value();
      std::vector<std::string> unacked;
      if (auto r = execute_plan(client, *out.second_pass, o.restore, &unacked); !r.ok()) {
        Error e = std::move(r).error();
        e.message = "second pass (a table differed after the reset): " + e.message;
        return fail(std::move(e));
      }
      for (auto& u : unacked) out.unacknowledged.push_back("second pass " + u);
      verify = verify_restore(client, out.plan, o.restore);
      if (!verify.ok()) {
        return fail(Error(verify.error().code,
                          "written, but verification could not read the drive back after the "
                          "second pass: " +
                              verify.error().message));
      }
    }
  }
  out.mismatches = std::move(verify->mismatches);
  out.stage = out.mismatches.empty() ? S::restored : S::verify_mismatch;
  // Steps the drive never acknowledged (ops/long_step.hpp): the read-back
  // decided. Matched: the record execute_plan kept for them goes.
  if (out.stage == S::restored && !out.unacknowledged.empty() && !o.restore.recovery_path.empty()) {
    if (auto r = remove_recovery(o.restore.recovery_path); !r.ok())
      return fail(std::move(r).error());
  }
  return out;
}

}  // namespace lmcfg::ops
