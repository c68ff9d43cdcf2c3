#pragma once
#include <functional>
// The console's HTML (serve/console.hpp): one function per page, from the
// Service's JSON answers. Every text from the inventory, a drive or the
// archive goes through report::html_escape (attributes too), names in URLs
// through url_encode.
#include <optional>
#include <string>

#include "fleet/inventory.hpp"
#include "serve/console.hpp"
#include "serve/console_words.hpp"

namespace lmcfg::serve::pages {

std::string signin(const std::string& message, const std::string& next, const std::string& csrf);
// Positions shown on one page of the overview.
inline constexpr std::size_t kOverviewRows = 100;
// The overview: counts of every position, then page `page` (from 1) of the
// rows the line and status filters match, with links to the pages beside it.
// `drives` needs name, line, id, status and last_backup of each position
// (Service::drive_summaries); `row`, when given, gives the whole state of
// each position shown (Service::drive), else `drives` holds it.
std::string overview(const ConsoleUser& u, bool signed_in, const fleet::Inventory& inv,
                     const Json& drives, const std::string& line, const std::string& status,
                     TimePoint now, std::size_t page = 1,
                     const std::function<Json(const Json&)>& row = {});
std::string position(const ConsoleUser& u, bool signed_in, const fleet::LineEntry& line,
                     const fleet::DriveEntry& d, const Json& state, const Result<Json>& history,
                     TimePoint now);
// `approved`: the approved revision's commit ("" = none), chosen unless `rev` names one.
std::string replace(const ConsoleUser& u, bool signed_in, const fleet::LineEntry& line,
                    const fleet::DriveEntry& d, const std::string& rev, const std::string& approved,
                    const Result<Json>& history);
std::string plan(const ConsoleUser& u, bool signed_in, const Json& plan, TimePoint now);
std::string job(const ConsoleUser& u, bool signed_in, const Json& job, const std::string& name);
std::string error(const ConsoleUser* u, bool signed_in, const std::string& title,
                  const std::string& message);
// A failed action in plain words: what happened and what to check, a button
// that tries again (`retry`: a form's action and fields, or a GET link when
// `retry_fields` is empty), the CLI's message folded below.
using Retry = RetryForm;
std::string failure(const ConsoleUser* u, bool signed_in, const std::string& title,
                    const words::Help& help, const std::string& cli_message, const Retry& retry,
                    const std::string& position);

// Pieces shared by the pages' files (console_pages.cpp, console_plan.cpp).
std::string esc(std::string_view s);
std::string str(const Json& j, const char* key);
// j[key] without undefined behaviour: null when j is not an object or lacks key.
const Json& member(const Json& j, const char* key);
std::string csrf_field(const ConsoleUser& u);
std::string frame(const ConsoleUser* u, bool signed_in, const std::string& title,
                  const std::string& body);
std::string badge(const std::string& status);
std::string name_html(const std::string& name);  // breaks only after a '/'
std::string position_link(const std::string& name);
std::string time_cell(const std::string& iso, TimePoint now);  // "3 min ago", UTC on hover
std::string local_time(const std::string& iso);  // the browser's local time, UTC on hover
// The CLI's wording, folded: <details>.
std::string cli_details(const std::string& message, std::optional<int> exit_code);
std::string help_html(const words::Help& h);
// The plan page's parts (console_plan.cpp), also lmcfg ui's: the steps as a
// table (name, UPID, now -> after in units) and a titled list of a plan's
// items (problems, losses, notes), "" when `items` is empty.
std::string steps_table(const Json& plan);
std::string items_section(const char* id, const char* title, const Json& items, const char* cls);
// The values that stay as the drive holds them by policy (ops::kept_json
// objects), each with the configuration's value, the drive's, why, and what
// the technician can do; "" when there are none. `id`: the list's id.
std::string kept_section(const Json& kept, const std::string& id, const std::string& intro);

// The status a person reads: "never backed up" for a position without a
// backup whose state is unknown, else the service's status.
std::string shown_status(const Json& drive);
// "3 h 12 min ago" from an ISO 8601 UTC time ("2026-11-24T17:20:15Z"); "" when unparsable.
std::string age(const std::string& iso, TimePoint now);

}  // namespace lmcfg::serve::pages
