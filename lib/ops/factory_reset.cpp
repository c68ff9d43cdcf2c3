#include "ops/factory_reset.hpp"

#include <algorithm>
#include <map>

#include "common/layers.hpp"
#include "config/model.hpp"
#include "db/database.hpp"
#include "ops/long_step.hpp"
#include "ops/recovery.hpp"
#include "ops/restore.hpp"

namespace lmcfg::ops {

namespace {

// One run of default_drive: its steps, and what a step that fails says.
class DefaultRun {
 public:
  DefaultRun(client::Client& c, const DefaultOptions& opt, const db::Database& db)
      : c_(c), opt_(opt), db_(db), record_(opt.recovery_path.string()) {}

  // Reads only: the communication values to keep, the undo record.
  Result<void> read_before();
  // The recovery record of an interrupted run, or a new one of the values to keep.
  Result<void> load_or_save_record();
  Result<void> default_layers();
  Result<void> write_back_kept();
  Result<void> delete_tables();
  Result<void> restart();
  DefaultReport& report() { return rep_; }

 private:
  bool selected(int layer) const { return opt_.layers[static_cast<std::size_t>(layer - 1)]; }
  Result<void> step(const std::string& what, Result<void> r);
  // A long operation as step `what` (ops/long_step.hpp): an answer that never
  // came is no failure once the drive answers again; true when acknowledged.
  Result<bool> long_op(const std::string& what, const std::string& waiting,
                       const std::function<Result<void>()>& op);
  // Tables saved without acknowledgement: after the restart RAM holds what
  // flash holds (§13.1), read it back: nothing must be left.
  Result<void> read_back_tables();

  client::Client& c_;
  const DefaultOptions& opt_;
  const db::Database& db_;
  const std::string record_;
  DefaultReport rep_;
  bool record_saved_ = false, mc_stopped_ = false, rom_changed_ = false;
  bool ct_unacked_ = false, curves_unacked_ = false, long_timed_out_ = false;
  // The communication values to keep, read before anything changes.
  std::map<std::uint16_t, std::uint32_t> keep_;
};

Result<void> DefaultRun::step(const std::string& what, Result<void> r) {
  if (!r.ok()) {
    Error e = std::move(r).error();
    const bool interrupted = e.code == make_error_code(Errc::interrupted);
    e.message =
        std::string(interrupted ? "interrupted at step '" : "stopped at step '") + what +
        "': " + e.message + (interrupted ? " (the telegram in flight was completed)" : "") +
        ". The drive is partially defaulted" + (mc_stopped_ ? " (MC stopped)" : "") +
        (long_timed_out_ ? ": once the drive answers, run the same command with longer waits"
                         : ": run the same command again") +
        (record_saved_ ? "; it finishes from the recovery record " + record_ : "") +
        (rep_.undo ? "; the previous values are in the undo record " + rep_.undo->path.string() +
                         " (" + rep_.undo->command + ")"
                   : std::string()) +
        ".";
    return e;
  }
  rep_.done.push_back(what);
  if (opt_.progress) opt_.progress("default", rep_.done.size(), 0);
  return {};
}

Result<bool> DefaultRun::long_op(const std::string& what, const std::string& waiting,
                                 const std::function<Result<void>()>& op) {
  auto r = long_step(c_, waiting, op);
  if (!r.ok()) {
    // Silent past both waits: the same waits would stop here again.
    long_timed_out_ = r.error().code == make_error_code(Errc::timeout);
    LMCFG_TRY(step(what, Result<void>(std::move(r).error())));
    return false;  // not reached: step() returned the error
  }
  if (!r->acknowledged) rep_.unacknowledged.push_back(what + ": " + r->note);
  LMCFG_TRY(step(what, Result<void>()));
  return r->acknowledged;
}

Result<void> DefaultRun::read_back_tables() {
  if (ct_unacked_) {
    auto ids = c_.ct_defined_entries();
    if (ids.ok() && !ids->empty())
      ids = Error(Errc::verify_mismatch, "the command table still defines " +
                                             std::to_string(ids->size()) +
                                             " entries after the restart: the unacknowledged "
                                             "save did not happen");
    LMCFG_TRY(step("read back the command table (empty)",
                   ids.ok() ? Result<void>() : Result<void>(std::move(ids).error())));
  }
  if (curves_unacked_) {
    for (std::uint16_t id = 1; id <= 100; ++id) {  // the storage limit (C1250 notes)
      auto sizes = c_.curve_sizes(id);
      if (sizes.ok() && *sizes)
        sizes = Error(Errc::verify_mismatch,
                      "curve " + std::to_string(id) +
                          " is still defined after the restart: the unacknowledged save did "
                          "not happen");
      if (!sizes.ok())
        return step("read back the curves (none)", Result<void>(std::move(sizes).error()));
    }
    LMCFG_TRY(step("read back the curves (none)", Result<void>()));
  }
  return {};
}

Result<void> DefaultRun::read_before() {
  std::array<std::optional<std::vector<client::ModifiedParam>>, 4> seen;  // for the undo record
  for (int layer = 1; layer <= 4; ++layer) {
    if (!selected(layer)) continue;
    LMCFG_ASSIGN_OR_RETURN(auto mods, c_.modified_list(layer));
    seen[static_cast<std::size_t>(layer - 1)] = mods;
    for (const auto& m : mods) {
      if (!is_comm_parameter(db_, m.upid)) continue;
      if (opt_.include_comm)  // LinUDP: UDP/IP whatever they hold (LinUDP V2 §3.2)
        rep_.link_may_change = c_.capabilities().protocol == "LinRS";
      else
        keep_[m.upid] = m.value;
    }
  }
  if (opt_.undo.enabled) {
    auto cfg = undo_config_for_default(c_, seen, opt_.curves, opt_.command_table, db_);
    if (!cfg.ok()) return std::move(cfg).error();  // reads only: nothing written
    LMCFG_ASSIGN_OR_RETURN(rep_.undo, save_undo(opt_.undo, *cfg, db_));
  }
  return {};
}

Result<void> DefaultRun::load_or_save_record() {
  if (opt_.recovery_path.empty()) return {};
  // An earlier run stopped after defaulting: the drive no longer shows the
  // values it had; the record holds them.
  LMCFG_ASSIGN_OR_RETURN(auto found, load_recovery(opt_.recovery_path));
  if (found) {
    rep_.recovery_note = "found the recovery record " + record_ + " of an interrupted run (" +
                         found->created + "): ";
    if (opt_.include_comm) {
      rep_.recovery_note +=
          "--include-comm defaults the communication values too, nothing to "
          "write back";
    } else {
      for (const auto& k : found->keep) {
        const int layer = lmcfg::layers::of_upid(k.upid);
        if (layer != 0 && selected(layer)) keep_[k.upid] = k.value;
      }
      rep_.recovered = true;
      rep_.recovery_note += "writing back the values it recorded";
    }
  }
  if (!keep_.empty() && !found) {
    RecoveryRecord r{"default", opt_.port, c_.options().id, utc_now(), {}, {}, {}};
    for (const auto& [upid, value] : keep_) r.keep.push_back({upid, value});
    LMCFG_TRY(save_recovery(opt_.recovery_path, r));
    rep_.recovery_note = "recorded the values to keep in " + record_;
  }
  record_saved_ = !keep_.empty() || found.has_value();
  return {};
}

Result<void> DefaultRun::default_layers() {
  LMCFG_TRY(step("stop MC", c_.stop_mc()));
  mc_stopped_ = true;
  for (int layer = 1; layer <= 4; ++layer) {
    if (!selected(layer)) continue;
    const std::string lname(lmcfg::layers::name(layer));
    LMCFG_ASSIGN_OR_RETURN(const bool acked,
                           long_op("default " + lname + " layer", "defaulting layer " + lname,
                                   [&] { return c_.default_layer(layer); }));
    rom_changed_ = true;
    if (acked) continue;
    // Unacknowledged: a defaulted layer lists no modified value (§10.2).
    auto mods = c_.modified_list(layer);
    if (mods.ok() && !mods->empty())
      mods = Error(Errc::verify_mismatch,
                   "the " + lname + " layer still lists " + std::to_string(mods->size()) +
                       " modified values: the unacknowledged defaulting did not happen");
    LMCFG_TRY(step("read back the " + lname + " layer (defaulted)",
                   mods.ok() ? Result<void>() : Result<void>(std::move(mods).error())));
  }
  return {};
}

Result<void> DefaultRun::write_back_kept() {
  for (const auto& [upid, value] : keep_) {
    char what[64];
    std::snprintf(what, sizeof what, "keep communication parameter %04Xh = %u", upid, value);
    LMCFG_TRY(step(what, c_.write_rom_confirmed(upid, value)));
  }
  // Every kept value read back (§10 05h 01h) before the record goes.
  for (const auto& [upid, value] : keep_) {
    char what[64];
    std::snprintf(what, sizeof what, "read back kept %04Xh", upid);
    auto back = c_.read_rom(upid);
    if (back.ok() && *back != value) {
      back = Error(Errc::verify_mismatch, "the drive holds " + std::to_string(*back) +
                                              ", expected " + std::to_string(value));
    }
    LMCFG_TRY(step(what, back.ok() ? Result<void>() : Result<void>(std::move(back).error())));
    rep_.kept.push_back({upid, value});
  }
  if (record_saved_) {
    LMCFG_TRY(remove_recovery(opt_.recovery_path));
    rep_.recovery_note += rep_.recovery_note.empty() ? "" : "; ";
    rep_.recovery_note +=
        keep_.empty() ? "record deleted" : "every kept value read back, record deleted";
  }
  return {};
}

Result<void> DefaultRun::delete_tables() {
  if (opt_.command_table) {
    LMCFG_TRY(step("delete all command table entries", c_.delete_all_ct()));
    LMCFG_ASSIGN_OR_RETURN(const bool acked, long_op("save command table to flash",
                                                     "saving the command table to flash",
                                                     [&] { return c_.save_ct(); }));
    ct_unacked_ = !acked;
  }
  if (opt_.curves) {
    LMCFG_TRY(step("delete all curves", c_.delete_all_curves()));
    LMCFG_ASSIGN_OR_RETURN(const bool acked,
                           long_op("save curves to flash", "saving the curves to flash",
                                   [&] { return c_.save_curves(); }));
    curves_unacked_ = !acked;
  }
  return {};
}

Result<void> DefaultRun::restart() {
  LMCFG_TRY(long_op("start MC", "starting MC", [&] { return c_.start_mc(); }));
  mc_stopped_ = false;
  if (!rom_changed_) return read_back_tables();
  // The drive answers after its restart (§13.1), already with its switch
  // settings; with the old link settings that answer can be lost: the
  // manual's wait only (ClientOptions::relink_reset_timeout).
  auto r = rep_.link_may_change
               ? c_.reset(std::min(c_.options().reset_timeout, c_.options().relink_reset_timeout))
               : c_.reset();
  if (!r.ok() && rep_.link_may_change && r.error().code == make_error_code(Errc::timeout)) {
    return step("reset (defaults become active; no answer with the old link settings)",
                Result<void>());
  }
  LMCFG_TRY(long_op("reset (defaults become active)", "resetting the drive",
                    [&]() { return std::move(r); }));
  return read_back_tables();
}

}  // namespace

Result<DefaultReport> default_drive(client::Client& c, const DefaultOptions& opt,
                                    const db::Database& db) {
  DefaultRun run(c, opt, db);
  LMCFG_TRY(run.read_before());
  LMCFG_TRY(run.load_or_save_record());
  LMCFG_TRY(run.default_layers());
  LMCFG_TRY(run.write_back_kept());
  LMCFG_TRY(run.delete_tables());
  LMCFG_TRY(run.restart());
  return std::move(run.report());
}

}  // namespace lmcfg::ops
