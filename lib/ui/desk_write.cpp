// The desk's writes (ui/desk.hpp): a plan shown on the page executed as
// `lmcfg restore` and `lmcfg undo` execute theirs, and the plan as the
// console's plan page reads it.
#include "ops/journal.hpp"
#include "ops/recovery.hpp"
#include "ops/restore_run.hpp"
#include "ops/undo.hpp"
#include "report/json_reports.hpp"
#include "serve/console_words.hpp"
#include "ui/desk_impl.hpp"

namespace lmcfg::ui {

namespace {

bool fresh(const ops::TargetSeen& t, const db::Database& db) {
  if ((t.ct_entries && !t.ct_entries->empty()) || (t.curves && !t.curves->empty())) return false;
  for (const auto& layer : t.layers)
    for (const auto& p : layer.value_or(std::vector<client::ModifiedParam>{}))
      if (!ops::is_comm_parameter(db, p.upid)) return false;
  return true;
}

}  // namespace

void Desk::Impl::run_execute(const std::string& job, const StoredPlan& sp, const ops::Audit& audit,
                             bool skip) {
  auto d = find_drive(sp.drive);
  if (!d) return fail(job, Error(Errc::not_found, "no drive '" + sp.drive + "'"));
  const auto id = static_cast<std::uint8_t>(d->link.id);
  ops::RestoreRunOptions ro;
  auto rec = ops::recovery_path("restore", d->link.port, id);
  auto dir = ops::undo_dir();
  if (!rec.ok()) return fail(job, rec.error());
  if (!dir.ok()) return fail(job, dir.error());
  ro.restore.recovery_path = *rec;
  ro.restore.port = d->link.port;
  ro.restore.skip_incompatible = skip;
  const ops::Plan* planned = &sp.plan;
  ro.restore.progress = [this, job, planned](const std::string& phase, std::size_t done,
                                             std::size_t total) {
    update(job, [&](DeskJob& j) {
      j.done = done;
      j.total = total;
      if (phase != "restore") {
        j.step = phase;
        return;
      }
      // Called as step `done` (1-based) begins.
      j.step_done = done > 0 ? done - 1 : 0;
      j.step = done > 0 && done <= planned->steps.size() ? planned->steps[done - 1].text
                                                         : "step " + std::to_string(done);
    });
  };
  const std::string command = sp.undo ? "undo" : "restore";
  ro.undo = ops::UndoOptions{true, *dir, d->link.port, id, command, ops::kUndoKeep};
  const std::string plan_id = sp.id;
  ro.confirm = [planned, plan_id](const ops::Plan& now) -> Result<ops::Consent> {
    const std::string what = ops::target_change(*planned, now);
    if (what.empty()) return ops::Consent::go;
    return Error(Errc::plan_refused, "the drive changed since plan " + plan_id + " was made (" +
                                         what + "); nothing written: make a new plan");
  };
  auto session = open(d->link);
  if (!session.ok()) return fail(job, session.error());
  const auto out = ops::run_restore(**session, sp.file, opt.db.get(), ro);
  auto closed = (*session)->close();
  auto err = ops::outcome_error(out);
  if (!err && !closed.ok() && out.written) err = closed.error();
  int code = err ? code_of(*err) : (out.skipped_any() ? 7 : 0);
  Json skipped = Json::array();
  for (const auto& s : out.plan.skipped_incompatible) skipped.push_back(s.text);
  std::size_t in_flight = 0;
  {
    std::lock_guard<std::mutex> lock(mu);
    in_flight = jobs.at(job).step_done;
  }
  update(job, [&](DeskJob& j) {
    j.result = Json{{"outcome", ops::outcome_name(out)},
                    {"file", sp.file_name},
                    {"skipped", skipped},
                    {"undo", out.undo ? Json(out.undo->path.string()) : Json(nullptr)},
                    {"undo_command", out.undo ? Json(out.undo->command) : Json(nullptr)}};
    if (err) {
      j.failed = true;
      j.message = err->message;
      j.exit_code = code;
      j.drive_state = serve::words::drive_state_after(out, in_flight);
    }
  });
  if (!out.written) return;
  ops::JournalEntry e;
  e.audit = audit;
  if (e.audit.who.empty()) e.audit.who = who();
  e.command = command;
  e.port = d->link.port;
  e.macid = id;
  e.file = sp.file_name;
  e.steps = report::restore_steps_json(out);
  e.outcome = ops::outcome_name(out);
  e.exit_code = code;
  e.exit_category = opt.exit_category ? opt.exit_category(code) : "";
  if (err) e.error = err->message;
  if (out.undo) e.undo = out.undo->path.string();
  auto path = ops::journal_path();
  auto written =
      path.ok() ? ops::append_journal(*path, ops::journal_record(e)) : Result<void>(path.error());
  if (!written.ok())
    update(job, [&](DeskJob& j) { j.result["journal_error"] = written.error().message; });
}

Result<Json> Desk::plan_json(const std::string& plan_id) const {
  std::lock_guard<std::mutex> lock(impl_->mu);
  auto it = impl_->plans.find(plan_id);
  if (it == impl_->plans.end())
    return Error(Errc::not_found, "no plan '" + plan_id + "' (a plan is used once, and expires)");
  const StoredPlan& sp = it->second;
  const auto& db = impl_->opt.db.get();
  const auto items = ops::plan_json(sp.plan);
  Json steps = Json::array();
  for (const auto& st : items["steps"]) {
    Json o;
    o["kind"] = st["action"];
    for (auto& [k, v] : st.items()) {
      if (k == "old" || k == "new") {
        o[k] = v.is_null() ? Json(nullptr) : Json(v["display"]);
        o[k + "_raw"] = v.is_null() ? Json(nullptr) : Json(v["raw"]);
      } else if (k != "action") {
        o[k] = v;
      }
    }
    if (st.contains("upid")) {
      const auto* p = db.find(
          static_cast<std::uint16_t>(std::stoul(st["upid"].get<std::string>(), nullptr, 16)));
      o["unit"] = p ? p->spec.unit : "";
    }
    steps.push_back(std::move(o));
  }
  Json problems = Json::array();
  for (const auto& p : sp.plan.problems) problems.push_back({{"kind", "plan"}, {"message", p}});
  Json incompatible = Json::array();
  std::size_t n = 0;
  for (const auto& v : items["skipped_incompatible"]) {
    Json o = v;
    o["message"] = sp.plan.skipped_incompatible[n++].text;
    incompatible.push_back(std::move(o));
  }
  auto d = impl_->drive_list.find(sp.drive);
  char id[8];
  std::snprintf(id, sizeof id, "%02Xh", d == impl_->drive_list.end() ? 0u : d->second.link.id);
  const auto secs = std::chrono::duration_cast<std::chrono::seconds>(
      sp.expires - std::chrono::system_clock::now());
  return Json{{"plan_id", sp.id},
              {"drive", sp.drive},
              {"port", d == impl_->drive_list.end() ? "" : d->second.link.port},
              {"id", id},
              {"file", sp.file_name},
              {"undo", sp.undo},
              {"expires_in_s", secs.count()},
              {"nothing_to_do", sp.plan.nothing_to_do()},
              {"steps", steps},
              {"losses", items["losses"]},
              {"notes", items["notes"]},
              {"problems", problems},
              {"incompatible", incompatible},
              {"factory_fresh", fresh(sp.plan.target, db)}};
}

}  // namespace lmcfg::ui
