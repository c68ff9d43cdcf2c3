#pragma once
// The console's HTML (serve/console.hpp): one function per page, from the
// Service's JSON answers. Every text from the inventory, a drive or the
// archive goes through report::html_escape (attributes too), names in URLs
// through url_encode.
#include <string>

#include "fleet/inventory.hpp"
#include "serve/console.hpp"

namespace lmcfg::serve::pages {

std::string signin(const std::string& message, const std::string& next, const std::string& csrf);
std::string overview(const ConsoleUser& u, bool signed_in, const fleet::Inventory& inv,
                     const Json& drives, const std::string& line, const std::string& status,
                     TimePoint now);
std::string position(const ConsoleUser& u, bool signed_in, const fleet::LineEntry& line,
                     const fleet::DriveEntry& d, const Json& state, const Result<Json>& history,
                     TimePoint now);
std::string replace(const ConsoleUser& u, bool signed_in, const fleet::LineEntry& line,
                    const fleet::DriveEntry& d, const std::string& rev,
                    const Result<Json>& history);
std::string plan(const ConsoleUser& u, bool signed_in, const Json& plan, TimePoint now);
std::string job(const ConsoleUser& u, bool signed_in, const Json& job, const std::string& name);
std::string error(const ConsoleUser* u, bool signed_in, const std::string& title,
                  const std::string& message);

// The status a person reads: "never backed up" for a position without a
// backup whose state is unknown, else the service's status.
std::string shown_status(const Json& drive);
// "3 h 12 min ago" from an ISO 8601 UTC time ("2026-11-24T17:20:15Z"); "" when unparsable.
std::string age(const std::string& iso, TimePoint now);

}  // namespace lmcfg::serve::pages
