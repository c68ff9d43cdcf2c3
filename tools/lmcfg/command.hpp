#pragma once
// Subcommand registry: each subcommand lives in its own cmd_*.cpp, registers
// itself at static-initialisation time, and stays a thin main over one library
// call. main.cpp only parses and dispatches.
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
  kInternal = 70,       // a bug: please report with --trace
  kInterrupted = 130,   // SIGINT/SIGTERM: stopped between two telegrams (128 + SIGINT)
};

// The setup function adds a subcommand to `app` and arranges (via the
// subcommand's callback) for `exit_code` to be set when it runs.
using Setup = std::function<void(CLI::App& app, int& exit_code)>;

struct Register {
  Register(int order, Setup setup);
};

}  // namespace lmcfg::cli
