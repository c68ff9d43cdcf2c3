// --reason/--ticket and the journal record of the writing commands.
#include "audit_flow.hpp"

#include <cstdio>

#include "command.hpp"

namespace lmcfg::cli {

void add_audit_options(CLI::App* sub, AuditFlags& f) {
  sub->add_option("--reason", f.reason,
                  "why this write is made: recorded in the journal and in the archive's commit "
                  "(Reason: trailer)");
  sub->add_option("--ticket", f.ticket,
                  "the ticket or work order of this write: recorded as --reason is (Ticket: "
                  "trailer)");
}

ops::Audit audit_of(const AuditFlags& f) { return {ops::current_user(), f.reason, f.ticket}; }

const char* exit_category(int code) {
  switch (code) {
    case kOk:
      return "ok";
    case kDifferent:
      return "different";
    case kInvalidInput:
      return "invalid_input";
    case kPlanRefused:
      return "plan_refused";
    case kCommFailure:
      return "comm_failure";
    case kDriveRefused:
      return "drive_refused";
    case kVerifyMismatch:
      return "verify_mismatch";
    case kRestoredExcept:
      return "restored_except";
    case kInternal:
      return "internal";
    case kInterrupted:
      return "interrupted";
  }
  return "other";
}

void record_in_journal(const char* command, ops::JournalEntry e) {
  e.exit_category = exit_category(e.exit_code);
  auto path = ops::journal_path();
  auto written =
      path.ok() ? ops::append_journal(*path, ops::journal_record(e)) : Result<void>(path.error());
  if (!written.ok())
    std::fprintf(stderr, "lmcfg %s: warning: not recorded in the journal: %s\n", command,
                 written.error().message.c_str());
}

}  // namespace lmcfg::cli
