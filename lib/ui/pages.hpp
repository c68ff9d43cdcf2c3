#pragma once
// The pages of `lmcfg ui` (docs/ui.md "Pages"): HTML from the desk's JSON,
// with the console's stylesheet, script, words and plan parts
// (serve/console_pages.hpp), so the plant console and this page say the same
// thing the same way. Every text from a drive, a file or a port goes through
// the console's escaping; every form carries the CSRF value.
#include <string>

#include "common/result.hpp"
#include "ui/desk.hpp"

namespace lmcfg::ui::pages {

// The frame: header with "Drives" and Quit, the page's body in <main>.
std::string frame(const std::string& title, const std::string& body, const std::string& csrf);
// Connect: the serial ports, the practice drive, a port or address typed in,
// "Find drives"; the drives found; the operations running.
std::string connect(const Json& ports, const Json& drives, const Json& jobs,
                    const std::string& folder, const std::string& csrf);
// One drive: identity and state in plain words, back up, compare, restore,
// undo, its backups in the folder and its journal.
std::string drive(const Json& d, const std::string& folder, const std::string& csrf);
// A job's progress (refreshed every second while it runs), then its outcome.
std::string job(const Json& j, const std::string& csrf);
// A restore's plan: the verdict first, the values with name, unit, now and
// after, then the confirmation with a reason.
std::string plan(const Json& p, const std::string& csrf);
// An error in plain words with what to check, the CLI's message folded.
std::string failure(const std::string& title, const Error& e, int exit_code,
                    const std::string& back, const std::string& csrf);
// After Quit.
std::string stopped();

// Hidden form fields of every page's forms: the CSRF value, and one named value.
std::string csrf_input(const std::string& csrf);
std::string hidden(const std::string& name, const std::string& value);
// Before the token: how to open the page.
std::string need_token();

}  // namespace lmcfg::ui::pages
