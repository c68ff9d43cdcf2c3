#include "fleet/history.hpp"

#include <ctime>

#include "common/utc_time.hpp"
#include "fleet/fleet.hpp"

namespace lmcfg::fleet {
std::string iso_utc(std::int64_t seconds) {
  const auto t = static_cast<std::time_t>(seconds);
  const std::tm tm = utc_tm(t);
  char buf[32];
  std::strftime(buf, sizeof buf, "%Y-%m-%dT%H:%M:%SZ", &tm);
  return buf;
}

namespace {

// The value of the first "captured_at" member in `text`, a drive
// configuration file as the archive keeps it (config/fields.cpp writes
// identity.captured_at among the first members): found without parsing the
// whole file, since only this one time is wanted of each.
std::optional<std::int64_t> captured_at(const std::string& text) {
  static const std::string key = "\"captured_at\"";
  const auto at = text.find(key);
  if (at == std::string::npos) return std::nullopt;
  const auto open = text.find('"', text.find(':', at + key.size()));
  if (open == std::string::npos) return std::nullopt;
  const auto close = text.find('"', open + 1);
  if (close == std::string::npos || close - open > 40) return std::nullopt;
  return parse_iso_utc(text.substr(open + 1, close - open - 1));
}

// "Name <email>" -> "Name" (the email stays in the JSON's author).
std::string author_name(const std::string& author) {
  const auto lt = author.find(" <");
  return lt == std::string::npos ? author : author.substr(0, lt);
}

}  // namespace

Result<std::vector<PositionEvent>> position_history(const Archive& archive, const DriveEntry& d,
                                                    std::size_t limit) {
  // fleet_restore's recording commit: "fleet restore: NAME <- NAME.json at ...";
  // " <- " ends the name, so "press3/z" does not take "press3/z-axis"'s.
  const std::string restored = "fleet restore: " + d.name + " <- ";
  auto is_restore = [&](const CommitInfo& c) { return c.summary.rfind(restored, 0) == 0; };
  LMCFG_ASSIGN_OR_RETURN(auto entries, archive.history(archive_path(d), limit, is_restore));
  std::vector<PositionEvent> out;
  out.reserve(entries.size());
  for (auto& e : entries) {
    PositionEvent ev;
    ev.kind = is_restore(e.commit) ? "restore" : "backup";
    for (const auto& [key, value] : message_trailers(e.commit.message)) {
      if (key == "Operator") ev.who = value;
      if (key == "Reason") ev.reason = value;
      if (key == "Ticket") ev.ticket = value;
    }
    if (ev.who.empty()) ev.who = author_name(e.author);
    ev.entry = std::move(e);
    out.push_back(std::move(ev));
  }
  return out;
}

Result<std::map<std::string, std::int64_t>> last_backup_times(const Archive& archive,
                                                              const std::vector<DriveEntry>& drives,
                                                              const std::string& rev) {
  std::map<std::string, std::int64_t> out;
  LMCFG_ASSIGN_OR_RETURN(auto commit, archive.resolve(rev));
  if (!commit) return out;  // no commit yet
  for (const auto& d : drives) {
    LMCFG_ASSIGN_OR_RETURN(auto text, archive.read(archive_path(d), commit->id));
    if (!text) continue;
    if (auto t = captured_at(*text)) out[d.name] = *t;
  }
  return out;
}

nlohmann::ordered_json history_json(const std::vector<PositionEvent>& events) {
  auto text_or_null = [](const std::string& s) {
    return s.empty() ? nlohmann::ordered_json(nullptr) : nlohmann::ordered_json(s);
  };
  nlohmann::ordered_json out = nlohmann::ordered_json::array();
  for (const auto& ev : events) {
    out.push_back({{"commit", ev.entry.commit.id},
                   {"time", iso_utc(ev.entry.time)},
                   {"kind", ev.kind},
                   {"who", ev.who},
                   {"reason", text_or_null(ev.reason)},
                   {"ticket", text_or_null(ev.ticket)},
                   {"subject", ev.entry.commit.summary},
                   {"author", ev.entry.author},
                   {"message", ev.entry.commit.message}});
  }
  return out;
}

std::string render_history(const std::vector<PositionEvent>& events, const std::string& name) {
  if (events.empty()) return "no history of " + name + " in the archive\n";
  std::string out;
  for (const auto& ev : events) {
    if (!out.empty()) out += "\n";
    out += iso_utc(ev.entry.time) + "  " + ev.entry.commit.id.substr(0, 12) + "  " + ev.kind +
           "  " + ev.who + "\n    " + ev.entry.commit.summary + "\n";
    if (!ev.reason.empty() || !ev.ticket.empty()) {
      out += "    why: " + (ev.reason.empty() ? std::string("-") : ev.reason);
      if (!ev.ticket.empty()) out += " (ticket " + ev.ticket + ")";
      out += "\n";
    }
  }
  return out;
}

}  // namespace lmcfg::fleet
