#pragma once
// The console's words for people (docs/console.md "Plain words"): what an
// error means for the technician in front of the drive and what to check, a
// plan step and a plan's verdict in a sentence. The CLI's wording of the same
// thing stays on the page, folded away; these functions never replace it.
#include <string>
#include <vector>

#include "common/result.hpp"
#include "ops/restore_run.hpp"
#include "serve/service.hpp"

namespace lmcfg::serve::words {

// An error as a technician reads it: one sentence, then what to check, in order.
struct Help {
  std::string sentence;
  std::vector<std::string> checklist;
};

// The kind of error behind a CLI exit code (docs/cli.md "Exit codes"), for
// the records that keep only the code and the message (a job, a position's
// last attempt). The one table the console reads codes through.
Errc errc_for_exit_code(int code);

// What went wrong and what to check, from the error's code and message.
// `position`: the position the action was about ("" when none).
Help help_for(const Error& e, const std::string& position);

// A restore job that failed, as the job page says it: the error's help, with
// what the drive holds now (`drive_state`, the job's) and whether the service
// retries by itself.
Help restore_failure_help(const Json& job, const std::string& position);

// What the drive holds after a restore that stopped at plan step `in_flight`
// (the steps before it done), in the words the position and job pages show:
// "untouched: ...", "partially configured, and its motion control is stopped:
// ...", "written, but it has not answered since its restart: ...".
std::string drive_state_after(const ops::RestoreOutcome& out, std::size_t in_flight);

// A message of the library without its citations: "(§13.3)" groups and
// "§12"-like references removed, for the page's headline (the CLI's wording
// keeps them, folded below).
std::string plain(const std::string& text);

// One plan step in words (the API's step: "kind", "layer", "id", "name", ...):
// "Stop motion control: the axis stops until the restore ends". Never a step's
// internal name or a section sign.
std::string step(const Json& st);

// A plan note (ops::Plan::notes, the CLI's wording) in a technician's words:
// what it means for the drive, without UPID database terms, telegrams or paths.
std::string note(const std::string& cli_note);

// A restore job's progress line (a plan step's CLI text, or a phase such as
// "plan: command table") in a technician's words: "Saving the command table to
// the drive's flash (10 s by the manual; some drives take a minute or more)".
// The manual's example allows 10 s (LinRS §12); real drives took 39 s for a
// command table and did not answer meanwhile (field reports, docs/field.md),
// so the page names both rather than promise the shorter one.
std::string progress(const std::string& cli_step);

// The plan's verdict, first on the plan page: "Will write 12 values and
// replace 3 curves; the axis stops during the restore." or "Cannot be
// restored as it stands: ...". `refused`: set when nothing can be written.
std::string verdict(const Json& plan, bool& refused);

}  // namespace lmcfg::serve::words
