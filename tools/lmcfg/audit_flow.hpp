#pragma once
// Who wrote and why (docs/audit.md): --reason and --ticket on every writing
// command, the OS user as "who", and the record each write appends to the
// local journal (ops/journal.hpp). Shared by restore, fleet restore, undo,
// default and set.
#include <CLI/CLI.hpp>
#include <string>

#include "ops/audit.hpp"
#include "ops/journal.hpp"

namespace lmcfg::cli {

struct AuditFlags {
  std::string reason;
  std::string ticket;
};

// --reason TEXT, --ticket ID.
void add_audit_options(CLI::App* sub, AuditFlags& f);

// The audit of this run: the OS user (ops::current_user) and the flags.
ops::Audit audit_of(const AuditFlags& f);

// The meaning of a documented exit code (README "Exit codes"), as the journal
// records it: "ok", "invalid_input", "plan_refused", "comm_failure",
// "drive_refused", "verify_mismatch", "restored_except", "interrupted", ...
const char* exit_category(int code);

// Appends `e` to the journal (exit_category filled in from exit_code). A
// journal that cannot be written never fails the command: "lmcfg COMMAND:
// warning: not recorded in the journal: ..." on stderr.
void record_in_journal(const char* command, ops::JournalEntry e);

}  // namespace lmcfg::cli
