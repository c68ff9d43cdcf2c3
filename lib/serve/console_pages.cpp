#include "serve/console_pages.hpp"

#include <cstdio>
#include <ctime>
#include <set>

#include "ops/report.hpp"

namespace lmcfg::serve::pages {

namespace {

std::string esc(std::string_view s) { return ops::html_escape(s); }

std::string str(const Json& j, const char* key) {
  auto it = j.find(key);
  return it != j.end() && it->is_string() ? it->get<std::string>() : std::string();
}

std::string csrf_field(const ConsoleUser& u) {
  return "<input type=\"hidden\" name=\"csrf\" value=\"" + esc(u.csrf) + "\">";
}

// The page around `body`: the stylesheet and script from this server only,
// a skip link, the navigation and who is signed in.
std::string frame(const ConsoleUser* u, bool signed_in, const std::string& title,
                  const std::string& body) {
  std::string o =
      "<!DOCTYPE html>\n<html lang=\"en\"><head><meta charset=\"utf-8\">"
      "<meta name=\"viewport\" content=\"width=device-width, initial-scale=1\">"
      "<title>" +
      esc(title) +
      " - lmcfg</title><link rel=\"stylesheet\" href=\"/console.css\">"
      "<script src=\"/console.js\" defer></script></head><body>\n"
      "<a class=\"skip\" href=\"#main\">Skip to content</a>\n"
      "<header><nav aria-label=\"Console\"><a class=\"brand\" href=\"/\">lmcfg plant</a>";
  if (u) {
    o += "<span class=\"who\">" + esc(u->who) + " (" + role_name(u->role) + ")</span>";
    if (signed_in)
      o += "<form method=\"post\" action=\"/signout\" class=\"inline\">" + csrf_field(*u) +
           "<button type=\"submit\">Sign out</button></form>";
  }
  o += "</nav></header>\n<main id=\"main\" tabindex=\"-1\">\n" + body + "</main>\n</body></html>\n";
  return o;
}

std::string badge(const std::string& status) {
  std::string cls = status;
  for (char& c : cls)
    if (c == ' ') c = '-';
  return "<span class=\"status s-" + esc(cls) + "\">" + esc(status) + "</span>";
}

std::string position_link(const std::string& name) {
  return "<a href=\"/position?name=" + esc(url_encode(name)) + "\">" + esc(name) + "</a>";
}

std::string time_cell(const std::string& iso, TimePoint now) {
  if (iso.empty()) return "<span class=\"muted\">never</span>";
  return "<time datetime=\"" + esc(iso) + "\" title=\"" + esc(iso) + "\">" + esc(age(iso, now)) +
         "</time>";
}

std::string last_event(const Json& d, TimePoint now) {
  std::string o = esc(str(d, "message"));
  const auto& a = d["last_attempt"];
  if (a.is_object())
    o += " <span class=\"muted\">(" + esc(str(a, "job")) + ", " + time_cell(str(a, "time"), now) +
         ")</span>";
  return o;
}

const char* const kStatuses[] = {"ok", "drift", "failed", "replaced", "unknown", "never backed up"};

std::string option(const std::string& value, const std::string& label, const std::string& chosen) {
  return "<option value=\"" + esc(value) + "\"" + (value == chosen ? " selected" : "") + ">" +
         esc(label) + "</option>";
}

// The archive's commit message: subject, body and the ops::Audit trailers.
struct Message {
  std::string subject;
  std::vector<std::pair<std::string, std::string>> trailers;  // Operator, Reason, Ticket
};
Message split_message(const std::string& m) {
  Message out;
  std::size_t pos = 0;
  bool first = true;
  while (pos <= m.size()) {
    auto end = m.find('\n', pos);
    if (end == std::string::npos) end = m.size();
    const std::string line = m.substr(pos, end - pos);
    pos = end + 1;
    if (first) {
      out.subject = line;
      first = false;
      continue;
    }
    for (const char* key : {"Operator", "Reason", "Ticket"}) {
      const std::string prefix = std::string(key) + ": ";
      if (line.rfind(prefix, 0) == 0) out.trailers.emplace_back(key, line.substr(prefix.size()));
    }
  }
  return out;
}

}  // namespace

std::string shown_status(const Json& d) {
  const std::string s = str(d, "status");
  if (s == "unknown" && !d["last_backup"].is_string()) return "never backed up";
  return s;
}

std::string age(const std::string& iso, TimePoint now) {
  std::tm tm{};
  if (std::sscanf(iso.c_str(), "%4d-%2d-%2dT%2d:%2d:%2dZ", &tm.tm_year, &tm.tm_mon, &tm.tm_mday,
                  &tm.tm_hour, &tm.tm_min, &tm.tm_sec) != 6)
    return "";
  tm.tm_year -= 1900;
  tm.tm_mon -= 1;
  const auto t = Clock::from_time_t(::timegm(&tm));
  const long long s = std::chrono::duration_cast<std::chrono::seconds>(now - t).count();
  if (s < 0) return "in the future (" + iso + ")";
  if (s < 60) return std::to_string(s) + " s ago";
  if (s < 3600) return std::to_string(s / 60) + " min ago";
  if (s < 86400)
    return std::to_string(s / 3600) + " h " + std::to_string(s % 3600 / 60) + " min ago";
  return std::to_string(s / 86400) + " d " + std::to_string(s % 86400 / 3600) + " h ago";
}

std::string signin(const std::string& message, const std::string& next, const std::string& csrf) {
  std::string b = "<h1>Sign in</h1>\n";
  if (!message.empty()) b += "<p class=\"problem\" role=\"alert\">" + esc(message) + "</p>\n";
  b += "<form method=\"post\" action=\"/signin\" class=\"card\">"
       "<input type=\"hidden\" name=\"csrf\" value=\"" +
       esc(csrf) + "\"><input type=\"hidden\" name=\"next\" value=\"" + esc(next) +
       "\">"
       "<label for=\"token\">Token</label>"
       "<input id=\"token\" name=\"token\" type=\"password\" autocomplete=\"current-password\" "
       "required autofocus>"
       "<p class=\"muted\">A token from <code>lmcfg serve token add</code> (viewer: read only; "
       "operator: also back up, plan and restore).</p>"
       "<button type=\"submit\">Sign in</button></form>\n";
  return frame(nullptr, true, "Sign in", b);
}

std::string overview(const ConsoleUser& u, bool signed_in, const fleet::Inventory& inv,
                     const Json& drives, const std::string& line, const std::string& status,
                     TimePoint now) {
  std::map<std::string, std::size_t> counts;
  for (const auto& d : drives) ++counts[shown_status(d)];
  std::string b = "<h1>Plant overview</h1>\n";
  b += "<section id=\"live\" data-refresh=\"10\" aria-live=\"polite\">\n";
  b += "<ul class=\"counts\" aria-label=\"Positions by status\"><li><strong>" +
       std::to_string(drives.size()) + "</strong> positions</li>";
  for (const char* s : kStatuses)
    b += "<li>" + badge(s) + " <strong data-count=\"" + esc(s) + "\">" + std::to_string(counts[s]) +
         "</strong></li>";
  b += "</ul>\n";
  b += "<p class=\"muted\">As of <time>" + esc(iso_time(now)) + "</time>.</p>\n";
  b += "<table class=\"positions\"><thead><tr><th scope=\"col\">Position</th><th "
       "scope=\"col\">Line</th><th scope=\"col\">ID</th><th scope=\"col\">Status</th><th "
       "scope=\"col\">Last backup</th><th scope=\"col\">Last event</th></tr></thead><tbody>\n";
  std::size_t shown = 0;
  for (const auto& d : drives) {
    const std::string st = shown_status(d);
    if (!line.empty() && str(d, "line") != line) continue;
    if (!status.empty() && st != status) continue;
    ++shown;
    char id[8];
    std::snprintf(id, sizeof id, "0x%02X", d["id"].get<unsigned>());
    b += "<tr data-drive=\"" + esc(str(d, "name")) + "\" data-status=\"" + esc(st) + "\"><td>" +
         position_link(str(d, "name")) + "</td><td>" + esc(str(d, "line")) + "</td><td>" + id +
         "</td><td>" + badge(st) + "</td><td>" + time_cell(str(d, "last_backup"), now) +
         "</td><td>" + last_event(d, now) + "</td></tr>\n";
  }
  if (shown == 0)
    b += "<tr><td colspan=\"6\" class=\"muted\">No position matches the filter.</td></tr>\n";
  b += "</tbody></table>\n</section>\n";
  // The filter is a plain GET form: it works without the script, and the
  // filtered view is a link one can keep.
  b += "<form method=\"get\" action=\"/\" class=\"filters\" aria-label=\"Filter\">"
       "<label for=\"f-line\">Line</label><select id=\"f-line\" name=\"line\">" +
       option("", "all lines", line);
  for (const auto& l : inv.lines) b += option(l.name, l.name, line);
  b += "</select><label for=\"f-status\">Status</label><select id=\"f-status\" name=\"status\">" +
       option("", "all", status);
  for (const char* s : kStatuses) b += option(s, s, status);
  b += "</select><button type=\"submit\">Filter</button></form>\n";
  return frame(&u, signed_in, "Plant overview", b);
}

std::string position(const ConsoleUser& u, bool signed_in, const fleet::LineEntry& line,
                     const fleet::DriveEntry& d, const Json& state, const Result<Json>& history,
                     TimePoint now) {
  std::string b = "<p class=\"crumbs\"><a href=\"/\">Plant</a> / " + esc(line.name) + "</p>\n";
  b += "<h1>" + esc(d.name) + " " + badge(shown_status(state)) + "</h1>\n";
  char id[8];
  std::snprintf(id, sizeof id, "0x%02X", d.id);
  b += "<section aria-labelledby=\"h-id\"><h2 id=\"h-id\">Identity</h2><dl class=\"identity\">";
  b += "<dt>Line</dt><dd>" + esc(line.name) + " (" + esc(line.port) + ")</dd>";
  b += "<dt>Drive ID</dt><dd>" + std::string(id) + "</dd>";
  for (const auto& [k, v] : d.labels) b += "<dt>" + esc(k) + "</dt><dd>" + esc(v) + "</dd>";
  b += "</dl></section>\n";

  b += "<section id=\"live\" data-refresh=\"10\" aria-labelledby=\"h-state\"><h2 "
       "id=\"h-state\">Current state</h2>";
  b += "<p>" + badge(shown_status(state)) + " " + esc(str(state, "message")) + "</p>";
  b += "<p>Last backup: " + time_cell(str(state, "last_backup"), now) +
       ". Last read: " + last_event(state, now) + ".</p>";
  if (state.contains("differing") && !state["differing"].empty()) {
    b += "<p>Differences from the archive at the last check:</p><ul class=\"differing\">";
    for (const auto& s : state["differing"]) b += "<li>" + esc(s.get<std::string>()) + "</li>";
    b += "</ul>";
  }
  b += "</section>\n";

  b += "<section aria-labelledby=\"h-act\"><h2 id=\"h-act\">Actions</h2>";
  if (u.role == Role::operator_) {
    b += "<form method=\"post\" action=\"/backup\" class=\"inline\">" + csrf_field(u) +
         "<input type=\"hidden\" name=\"name\" value=\"" + esc(d.name) +
         "\"><button type=\"submit\" id=\"backup-now\">Back up now</button></form>";
  } else {
    b += "<p class=\"muted\">Signed in as a viewer: you can look at everything and change "
         "nothing.</p>";
  }
  b += "</section>\n";

  b += "<section aria-labelledby=\"h-hist\"><h2 id=\"h-hist\">History</h2>";
  if (!history.ok()) {
    b += "<p class=\"problem\">" + esc(history.error().message) + "</p>";
  } else if (history->empty()) {
    b += "<p class=\"muted\">Not in the archive yet.</p>";
  } else {
    b += "<ol class=\"timeline\">";
    for (const auto& h : *history) {
      const Message m = split_message(str(h, "message"));
      const std::string commit = str(h, "commit");
      b += "<li data-commit=\"" + esc(commit) + "\"><time datetime=\"" + esc(str(h, "time")) +
           "\">" + esc(str(h, "time")) + "</time> <code>" + esc(commit.substr(0, 10)) +
           "</code> <span class=\"subject\">" + esc(m.subject) +
           "</span><br><span class=\"muted\">" + esc(str(h, "author")) + "</span>";
      if (!m.trailers.empty()) {
        b += "<dl class=\"trailers\">";
        for (const auto& [k, v] : m.trailers) b += "<dt>" + esc(k) + "</dt><dd>" + esc(v) + "</dd>";
        b += "</dl>";
      }
      b += "</li>";
    }
    b += "</ol>";
  }
  b += "</section>\n";
  return frame(&u, signed_in, d.name, b);
}

std::string job(const ConsoleUser& u, bool signed_in, const Json& j, const std::string& name) {
  const std::string state = str(j, "state");
  std::string b;
  if (!name.empty())
    b += "<p class=\"crumbs\"><a href=\"/\">Plant</a> / " + position_link(name) + "</p>\n";
  b += "<h1>Job " + esc(str(j, "id")) + ": " + esc(str(j, "kind")) + " of " + esc(str(j, "scope")) +
       "</h1>\n";
  // While the job runs the script reloads this section; without it, the
  // page's own reload does the same.
  b += std::string("<section id=\"live\" aria-live=\"polite\"") +
       (state == "done" ? "" : " data-refresh=\"1\"") + ">";
  const auto total = j.value("drives", 0u), done = j.value("done", 0u);
  b += "<p>State: <strong class=\"job-state\" data-state=\"" + esc(state) + "\">" + esc(state) +
       "</strong></p>";
  b += "<progress max=\"" + std::to_string(total ? total : 1) + "\" value=\"" +
       std::to_string(done) + "\">" + std::to_string(done) + " of " + std::to_string(total) +
       "</progress> " + std::to_string(done) + " of " + std::to_string(total) + " drive(s)";
  if (j.contains("counts")) {
    b += "<ul class=\"counts\">";
    for (const auto& [k, v] : j["counts"].items())
      b += "<li>" + esc(k) + " <strong>" + v.dump() + "</strong></li>";
    b += "</ul>";
  }
  if (j.contains("commits") && !j["commits"].empty()) {
    b += "<p>Committed:</p><ul>";
    for (const auto& c : j["commits"])
      b += "<li><code>" + esc(c.get<std::string>()) + "</code></li>";
    b += "</ul>";
  }
  if (j.contains("errors") && !j["errors"].empty()) {
    b += "<p class=\"problem\">Errors:</p><ul>";
    for (const auto& e : j["errors"]) b += "<li>" + esc(e.get<std::string>()) + "</li>";
    b += "</ul>";
  }
  b += "</section>\n";
  if (!name.empty())
    b += "<p><a href=\"/position?name=" + esc(url_encode(name)) + "\">Back to " + esc(name) +
         "</a></p>\n";
  return frame(&u, signed_in, "Job " + str(j, "id"), b);
}

std::string error(const ConsoleUser* u, bool signed_in, const std::string& title,
                  const std::string& message) {
  return frame(u, signed_in, title,
               "<h1>" + esc(title) + "</h1>\n<p class=\"problem\" role=\"alert\">" + esc(message) +
                   "</p>\n<p><a href=\"/\">Plant overview</a></p>\n");
}

}  // namespace lmcfg::serve::pages
