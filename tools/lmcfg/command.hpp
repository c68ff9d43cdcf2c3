#pragma once
// The subcommands: each lives in its own cmd_*.cpp as an add_NAME() that adds
// it to the app and stays a thin main over one library call. main.cpp lists
// them in one table (their order is the order of --help) and dispatches.
#include <CLI/CLI.hpp>
#include <functional>
#include <string>

namespace lmcfg::cli {

// Documented exit codes (README "Exit codes"). Stable: users' scripts depend on them.
enum Exit : int {
  kOk = 0,
  kDifferent = 1,       // diff: configurations differ
  kInvalidInput = 2,    // bad file, bad option value: nothing written
  kPlanRefused = 3,     // restore plan found problems: nothing written
  kCommFailure = 4,     // no answer, link lost, garbled telegrams
  kDriveRefused = 5,    // the drive answered with an error state (C1..C9) or refused
  kVerifyMismatch = 6,  // written, but reading back differs from the file
  kRestoredExcept = 7,  // restore --skip-incompatible: restored except the listed values, verified
  kInternal = 70,       // a bug: please report with --trace
  kInterrupted = 130,   // SIGINT/SIGTERM: stopped between two telegrams (128 + SIGINT)
};

// Each adds its subcommand to `app` and arranges (via the subcommand's
// callback) for `exit_code` to be set when it runs.
void add_backup(CLI::App& app, int& exit_code);
void add_diff(CLI::App& app, int& exit_code);
void add_report(CLI::App& app, int& exit_code);
void add_restore(CLI::App& app, int& exit_code);
void add_default(CLI::App& app, int& exit_code);
void add_undo(CLI::App& app, int& exit_code);
void add_journal(CLI::App& app, int& exit_code);
void add_get(CLI::App& app, int& exit_code);
void add_set(CLI::App& app, int& exit_code);
void add_db(CLI::App& app, int& exit_code);
void add_info(CLI::App& app, int& exit_code);
void add_convert(CLI::App& app, int& exit_code);
void add_scan(CLI::App& app, int& exit_code);
void add_link(CLI::App& app, int& exit_code);
void add_sim(CLI::App& app, int& exit_code);
void add_fleet(CLI::App& app, int& exit_code);
void add_serve(CLI::App& app, int& exit_code);
void add_ui(CLI::App& app, int& exit_code);

}  // namespace lmcfg::cli
