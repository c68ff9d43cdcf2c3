#pragma once
// The restore flow shared by `lmcfg restore`, `lmcfg undo` and `lmcfg fleet
// restore`, for both protocols: the options, the confirmation on a terminal,
// the library's run (ops::run_restore for LinRS, ops::run_devicenet_restore
// for DeviceNet: devicenet_flow.hpp), and the text or JSON report, journal
// record and exit code of each outcome.
#include <CLI/CLI.hpp>
#include <cstdint>
#include <functional>
#include <nlohmann/json.hpp>
#include <string>

#include "audit_flow.hpp"
#include "config/model.hpp"
#include "link_options.hpp"
#include "ops/restore_run.hpp"

namespace lmcfg::cli {

struct RestoreFlags {
  bool dry_run = false;
  bool no_default = false;
  bool include_comm = false;
  bool no_reset = false;
  bool skip_incompatible = false;
  bool yes = false;
  bool no_undo = false;
  std::string family;  // --family: the target's drive family (docs/families.md)
  ReconnectOptions reconnect;
  // The command that saves the undo record (its file name) and that the
  // journal names: "restore", "fleet-restore", "undo".
  std::string undo_name = "restore";
  AuditFlags audit;      // --reason, --ticket
  std::string position;  // fleet restore: the position's name, for the journal
};

// --dry-run, --no-default, --include-comm, --reconnect-*, --yes, --no-reset,
// --skip-incompatible, --no-undo, --family, --reason, --ticket.
void add_restore_flags(CLI::App* sub, RestoreFlags& f);

// What the shared steps say of the target of a restore.
struct RestoreTarget {
  std::string noun = "drive";  // "drive", "controller": "restore FILE onto a drive"
  std::string question;        // "Write this plan to drive 11h on /dev/ttyUSB0?"
  std::uint8_t macid = 0;      // for the journal
  // The plan is printed before the question with --yes too (unless --quiet or
  // --json): a DeviceNet restore's Set commands are few, and a log of a
  // scripted restore should say what was written.
  bool plan_with_yes = false;
  std::function<unsigned long long()> telegrams;  // LinRS: for the summary
  ProgressBar* bar = nullptr;                     // the run's progress bar, ended before any output
};

// Before the first write: the plan (`plan`, its text; on stdout, on stderr when
// stdout carries the JSON report) unless --yes, then the question (--yes:
// none; no terminal: refused).
Result<ops::Consent> confirm_restore(const std::string& plan, const RestoreTarget& t,
                                     const std::string& file_name, const CommonOptions& common,
                                     const RestoreFlags& f);

// After the library's run, either protocol: the JSON report (--json) or the
// outcome's text, the undo note, the journal record when anything was
// written; the documented exit code.
int finish_restore(const ops::RestoreOutcome& out, const RestoreTarget& t,
                   const std::string& file_name, const CommonOptions& common,
                   const RestoreFlags& f);

// Restores `file` (called `file_name` in messages) over `session` as `lmcfg
// restore` does, printing the plan, the confirmation and the outcome; returns
// the documented exit code. When anything was written, the run is recorded in
// the journal (audit_flow.hpp). `overrides` come from relink_overrides(f.reconnect),
// checked by the caller before the link opened.
// "undo: saved the target's previous values to PATH; to put them back: CMD"
// on stderr (unless --quiet or --json).
void print_undo_saved(const ops::UndoSaved& u, const CommonOptions& common);

int restore_on_session(link::Session& session, const config::DriveConfig& file,
                       const std::string& file_name, const CommonOptions& common,
                       const RestoreFlags& f, const link::RelinkOverrides& overrides,
                       const db::Database& db, ops::RestoreOutcome& out);

}  // namespace lmcfg::cli
