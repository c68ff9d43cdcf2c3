#include "serve/console_pages.hpp"

#include <cstdio>
#include <ctime>
#include <map>
#include <set>

#include "common/utc_time.hpp"
#include "report/report.hpp"
#include "serve/console_words.hpp"

namespace lmcfg::serve::pages {

std::string esc(std::string_view s) { return report::html_escape(s); }

const Json& member(const Json& j, const char* key) {
  // operator[] of a const json on a missing key is undefined behaviour.
  static const Json kNull;
  if (!j.is_object()) return kNull;
  auto it = j.find(key);
  return it == j.end() ? kNull : *it;
}

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
  // The script shows the banner when the service stops answering (console.js).
  o += "</nav></header>\n<div id=\"offline\" class=\"banner\" hidden></div>\n"
       "<main id=\"main\" tabindex=\"-1\">\n" +
       body + "</main>\n</body></html>\n";
  return o;
}

std::string badge(const std::string& status) {
  std::string cls = status;
  for (char& c : cls)
    if (c == ' ') c = '-';
  return "<span class=\"status s-" + esc(cls) + "\">" + esc(status) + "</span>";
}

std::string name_html(const std::string& name) {
  // A line may break after a '/' of "press3/feeder", never inside a word.
  std::string o = "<span class=\"name\">";
  std::size_t pos = 0;
  for (auto slash = name.find('/'); slash != std::string::npos; slash = name.find('/', pos)) {
    o += esc(name.substr(pos, slash + 1 - pos)) + "<wbr>";
    pos = slash + 1;
  }
  return o + esc(name.substr(pos)) + "</span>";
}

std::string position_link(const std::string& name) {
  return "<a href=\"/position?name=" + esc(url_encode(name)) + "\">" + name_html(name) + "</a>";
}

std::string time_cell(const std::string& iso, TimePoint now) {
  if (iso.empty()) return "<span class=\"muted\">never</span>";
  // The script adds the browser's local time to the title; UTC stays there.
  return "<time datetime=\"" + esc(iso) + "\" title=\"" + esc(iso) + "\">" + esc(age(iso, now)) +
         "</time>";
}

std::string local_time(const std::string& iso) {
  // Shown in the browser's local time by the script; without it, UTC as written.
  return "<time class=\"abs\" datetime=\"" + esc(iso) + "\" title=\"" + esc(iso) + "\">" +
         esc(iso) + "</time>";
}

std::string cli_details(const std::string& message, std::optional<int> exit_code) {
  if (message.empty() && !exit_code) return "";
  std::string o = "<details class=\"cli\"><summary>As the command line says it</summary>";
  if (!message.empty()) o += "<p><code class=\"wrap\">" + esc(message) + "</code></p>";
  if (exit_code) o += "<p>Exit code " + std::to_string(*exit_code) + " (docs/cli.md).</p>";
  return o + "</details>";
}

std::string help_html(const words::Help& h) {
  std::string o =
      "<p class=\"problem\" role=\"alert\" id=\"what-happened\">" + esc(h.sentence) + "</p>";
  if (!h.checklist.empty()) {
    o += "<p>What to check:</p><ol class=\"checklist\">";
    for (const auto& c : h.checklist) o += "<li>" + esc(c) + "</li>";
    o += "</ol>";
  }
  return o;
}

namespace {

words::Help failed_help(const Json& state, const std::string& name);

// The position's last event: a failure in a technician's words, the service's
// message (the CLI's wording, which may name options, codes or paths) folded.
std::string last_event(const Json& d, TimePoint now) {
  std::string o = esc(str(d, "message"));
  if (str(d, "status") == "failed")
    o = "<details class=\"event\"><summary>" + esc(failed_help(d, str(d, "name")).sentence) +
        "</summary>" + o + "</details>";
  const auto& a = member(d, "last_attempt");
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
  if (s == "unknown" && !member(d, "last_backup").is_string()) return "never backed up";
  return s;
}

std::string age(const std::string& iso, TimePoint now) {
  const auto seconds = parse_iso_utc(iso);
  if (!seconds) return "";
  const auto t = Clock::from_time_t(static_cast<std::time_t>(*seconds));
  const long long s = std::chrono::duration_cast<std::chrono::seconds>(now - t).count();
  if (s < 0) {  // a deadline (a plan's expiry)
    const long long f = -s;
    if (f < 60) return "in " + std::to_string(f) + " s";
    if (f < 3600) return "in " + std::to_string(f / 60) + " min";
    return "in " + std::to_string(f / 3600) + " h " + std::to_string(f % 3600 / 60) + " min";
  }
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

// No backup of the position yet, whatever its status (a first backup that
// failed too): the rows then say "Last backup: never".
static bool never_backed_up(const Json& d) { return !member(d, "last_backup").is_string(); }

std::string overview(const ConsoleUser& u, bool signed_in, const fleet::Inventory& inv,
                     const Json& drives, const std::string& line, const std::string& status,
                     TimePoint now, std::size_t page, const std::function<Json(const Json&)>& row) {
  // The counts agree with the rows: "never backed up" counts every position
  // whose row says "Last backup: never", beside its status.
  std::map<std::string, std::size_t> counts;
  for (const auto& d : drives) {
    const std::string st = shown_status(d);
    if (st != "never backed up") ++counts[st];
    counts["never backed up"] += never_backed_up(d);
  }
  std::string b = "<h1>Plant overview</h1>\n";
  b += "<section id=\"live\" data-refresh=\"10\" aria-live=\"polite\">\n";
  b += "<ul class=\"counts\" aria-label=\"Positions by status\"><li><strong>" +
       std::to_string(drives.size()) + "</strong> positions</li>";
  for (const char* s : kStatuses)
    b += "<li>" + badge(s) + " <strong data-count=\"" + esc(s) + "\">" + std::to_string(counts[s]) +
         "</strong></li>";
  b += "</ul>\n";
  b += "<p class=\"muted\">As of " + local_time(iso_time(now)) + ".</p>\n";
  b += "<table class=\"positions\"><thead><tr><th scope=\"col\">Position</th><th "
       "scope=\"col\">Line</th><th scope=\"col\">ID</th><th scope=\"col\">Status</th><th "
       "scope=\"col\">Last backup</th><th scope=\"col\">Last event</th></tr></thead><tbody>\n";
  // A page of kOverviewRows positions of those the filter matches: a plant
  // of thousands stays a page a browser draws at once.
  const std::size_t first = (std::max<std::size_t>(page, 1) - 1) * kOverviewRows;
  std::size_t matched = 0;
  for (const auto& summary : drives) {
    const std::string st = shown_status(summary);
    if (!line.empty() && str(summary, "line") != line) continue;
    if (!status.empty() && st != status &&
        !(status == "never backed up" && never_backed_up(summary)))
      continue;
    if (matched++ < first || matched > first + kOverviewRows) continue;
    const Json whole = row ? row(summary) : Json();
    const Json& d = row ? whole : summary;
    char id[8];
    std::snprintf(id, sizeof id, "0x%02X", member(d, "id").get<unsigned>());
    // data-label: each cell's heading where a narrow screen shows a row as a card.
    b += "<tr data-drive=\"" + esc(str(d, "name")) + "\" data-status=\"" + esc(st) + "\"><td>" +
         position_link(str(d, "name")) + "</td><td data-label=\"Line\">" + esc(str(d, "line")) +
         "</td><td data-label=\"ID\">" + id + "</td><td>" + badge(st) +
         "</td><td data-label=\"Last backup\">" + time_cell(str(d, "last_backup"), now) +
         "</td><td data-label=\"Last event\">" + last_event(d, now) + "</td></tr>\n";
  }
  if (matched <= first)
    b += "<tr><td colspan=\"6\" class=\"muted\">" +
         std::string(matched ? "No position on this page." : "No position matches the filter.") +
         "</td></tr>\n";
  b += "</tbody></table>\n";
  if (matched > kOverviewRows) {
    const std::size_t pages = (matched + kOverviewRows - 1) / kOverviewRows,
                      at = first / kOverviewRows + 1;
    auto link = [&](std::size_t to, const char* text) {
      return "<a href=\"/?line=" + esc(url_encode(line)) +
             "&amp;status=" + esc(url_encode(status)) + "&amp;page=" + std::to_string(to) + "\">" +
             text + "</a>";
    };
    b += "<nav class=\"pages\" aria-label=\"Pages\"><p>Positions " + std::to_string(first + 1) +
         "-" + std::to_string(std::min(matched, first + kOverviewRows)) + " of " +
         std::to_string(matched) + " (page " + std::to_string(at) + " of " + std::to_string(pages) +
         ")";
    if (at > 1) b += " &middot; " + link(std::min(at, pages + 1) - 1, "Previous page");
    if (at < pages) b += " &middot; " + link(at + 1, "Next page");
    b += "</p></nav>\n";
  }
  b += "</section>\n";
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

namespace {

// The position's history: each revision with its links, the approval form
// (operators) or the mark of the approved one; the form comparing two revisions.
std::string history_section(const ConsoleUser& u, const fleet::DriveEntry& d, const Json& approved,
                            const Result<Json>& history) {
  const std::string enc = esc(url_encode(d.name));
  std::string b;
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
      b += "<li data-commit=\"" + esc(commit) + "\">" + local_time(str(h, "time")) + " <code>" +
           esc(commit.substr(0, 10)) + "</code> <span class=\"subject\">" + esc(m.subject) +
           "</span><br><span class=\"muted\">" + esc(str(h, "author")) + "</span>";
      if (!m.trailers.empty()) {
        b += "<dl class=\"trailers\">";
        for (const auto& [k, v] : m.trailers) b += "<dt>" + esc(k) + "</dt><dd>" + esc(v) + "</dd>";
        b += "</dl>";
      }
      const std::string rev = esc(url_encode(commit));
      b += "<p class=\"links\"><a href=\"/report?name=" + enc + "&amp;rev=" + rev +
           "\">report</a> &middot; <a href=\"/diff?name=" + enc + "&amp;from=" + rev +
           "&amp;to=live\">diff with the drive</a>";
      if (u.role == Role::operator_)
        b += " &middot; <a href=\"/replace?name=" + enc + "&amp;rev=" + rev +
             "\">restore this revision</a>";
      b += "</p>";
      if (approved.is_object() && str(approved, "rev") == commit) {
        b += "<p class=\"approved\">This is the approved configuration.</p>";
      } else if (u.role == Role::operator_ && str(h, "kind") == "backup") {
        // What the position should hold from now on: a person decides, and says why.
        b += "<form method=\"post\" action=\"/approve\" class=\"inline approve\">" + csrf_field(u) +
             "<input type=\"hidden\" name=\"name\" value=\"" + esc(d.name) +
             "\"><input type=\"hidden\" name=\"rev\" value=\"" + esc(commit) +
             "\"><label>Why <input name=\"reason\" required></label> <label>Ticket <input "
             "name=\"ticket\"></label> <button type=\"submit\">Approve this "
             "revision</button></form>";
      }
      b += "</li>";
    }
    b += "</ol>";
    // Any two revisions: a GET form, so the diff is a link one can keep.
    auto revisions = [&](const char* field, const char* label, std::size_t chosen, bool live) {
      std::string o = "<label for=\"d-" + std::string(field) + "\">" + label +
                      "</label><select id=\"d-" + field + "\" name=\"" + field + "\">";
      if (live) o += "<option value=\"live\">the drive now</option>";
      std::size_t n = 0;
      for (const auto& h : *history) {
        const std::string c = str(h, "commit");
        o += "<option value=\"" + esc(c) + "\"" + (n++ == chosen && !live ? " selected" : "") +
             ">" + esc(str(h, "time")) + " " + esc(c.substr(0, 10)) + "</option>";
      }
      return o + "</select>";
    };
    b += "<form method=\"get\" action=\"/diff\" class=\"filters\" aria-label=\"Compare revisions\">"
         "<input type=\"hidden\" name=\"name\" value=\"" +
         esc(d.name) + "\">" + revisions("from", "Compare", history->size() > 1 ? 1 : 0, false) +
         revisions("to", "with", 0, false) + "<button type=\"submit\">Diff</button></form>";
  }
  return b;
}

// A failed position in words: a restore's failure with what the drive holds,
// or the read that failed (the CLI's exit code of the attempt says which kind).
words::Help failed_help(const Json& state, const std::string& name) {
  const Json& a = member(state, "last_attempt");
  const int code =
      a.is_object() && member(a, "exit_code").is_number() ? member(a, "exit_code").get<int>() : 0;
  if (a.is_object() && str(a, "job") == "restore") {
    Json job{{"message", str(state, "message")}, {"exit_code", code}};
    job["drive_state"] = str(state, "drive_state");
    auto h = words::restore_failure_help(job, name);
    return h;
  }
  return words::help_for(Error(words::errc_for_exit_code(code), str(state, "message")), name);
}

// After a failed restore: what the drive holds, and the automatic retry
// waiting for it (who asked for the restore, what the retry will do, and for
// operators the button that cancels it).
std::string retry_section(const ConsoleUser& u, const fleet::DriveEntry& d, const Json& state) {
  std::string b;
  const Json& r = member(state, "retry");
  if (!r.is_object()) return b;
  b += "<div class=\"amber\" id=\"retry\"><p><strong>";
  if (r.value("running", false))
    b += "The automatic retry is running now";
  else
    b += "An automatic retry is waiting";
  b += "</strong>";
  if (member(r, "of_job").is_string())
    b += ": automatic retry of <a href=\"/job?id=" + esc(url_encode(str(r, "of_job"))) +
         "&amp;name=" + esc(url_encode(d.name)) + "\">job " + esc(str(r, "of_job")) + "</a>";
  if (!str(r, "asked_by").empty()) b += " (asked by " + esc(str(r, "asked_by")) + ")";
  b += ". It will " + esc(str(r, "will")) + ".</p>";
  // Each automatic attempt that failed (when, why) and when the next is due.
  const Json& fails = member(r, "failures");
  if (fails.is_array() && !fails.empty()) {
    b += "<p>" + std::to_string(r.value("failed_attempts", fails.size())) +
         " automatic attempt(s) failed so far" +
         (member(r, "next_attempt").is_string()
              ? "; the next is due at " + esc(str(r, "next_attempt"))
              : std::string()) +
         ":</p><ul id=\"retry-failures\">";
    for (const auto& f : fails)
      b += "<li>" + esc(str(f, "time")) + ", job " + esc(str(f, "job")) + ": " +
           esc(str(f, "reason")) + "</li>";
    b += "</ul>";
  }
  if (u.role == Role::operator_ && !r.value("running", false))
    b += "<form method=\"post\" action=\"/cancel-retry\" class=\"inline\">" + csrf_field(u) +
         "<input type=\"hidden\" name=\"name\" value=\"" + esc(d.name) +
         "\"><button type=\"submit\" id=\"cancel-retry\">Cancel the automatic "
         "retry</button></form> <span class=\"muted\">The drive then stays as it is until "
         "someone restores it.</span>";
  return b + "</div>";
}

}  // namespace

std::string position(const ConsoleUser& u, bool signed_in, const fleet::LineEntry& line,
                     const fleet::DriveEntry& d, const Json& state, const Result<Json>& history,
                     TimePoint now) {
  const std::string enc = esc(url_encode(d.name));
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
  if (str(state, "status") == "failed") {
    // What went wrong in words; the service's message (the CLI's) folded.
    const Json& a = member(state, "last_attempt");
    b += "<p>" + badge("failed") + "</p>" + help_html(failed_help(state, d.name));
    const std::string message = str(state, "message");
    if (message.rfind("automatic retry cancelled by ", 0) == 0)
      b += "<p id=\"retry-cancelled\"><strong>" + esc(message) + ".</strong></p>";
    b += "<p>Last backup: " + time_cell(str(state, "last_backup"), now) + ". Last attempt: " +
         (a.is_object() ? esc(str(a, "job")) + ", " + time_cell(str(a, "time"), now) : "none") +
         ".</p>" + cli_details(str(state, "message"), std::nullopt);
  } else {
    b += "<p>" + badge(shown_status(state)) + " " + esc(str(state, "message")) + "</p>";
    b += "<p>Last backup: " + time_cell(str(state, "last_backup"), now) +
         ". Last read: " + last_event(state, now) + ".</p>";
  }
  const Json approved = state.contains("approved") ? member(state, "approved") : Json();
  if (approved.is_object()) {
    b += "<p id=\"approved\">Approved configuration: <code>" +
         esc(str(approved, "rev").substr(0, 10)) + "</code>, approved by " +
         esc(str(approved, "who")) + " " + time_cell(str(approved, "time"), now) + ": " +
         esc(str(approved, "reason")) + "</p>";
  }
  if (state.contains("differing") && !member(state, "differing").empty()) {
    b += "<p>Differences at the last check (each as the approved configuration &rarr; the "
         "drive):</p><ul class=\"differing\">";
    for (const auto& s : member(state, "differing"))
      b += "<li>" + esc(s.get<std::string>()) + "</li>";
    b += "</ul>";
  }
  b += kept_section(member(state, "kept"), "kept",
                    "These values differ from the approved configuration, but the drive keeps "
                    "them by policy: the position is ok with them.");
  b += retry_section(u, d, state);
  b += "</section>\n";

  b += "<section aria-labelledby=\"h-act\"><h2 id=\"h-act\">Actions</h2>";
  b += "<p><a href=\"/diff?name=" + enc +
       "&amp;from=HEAD&amp;to=live\" id=\"live-diff\">Live diff against the archive</a> "
       "(reads the drive now) &middot; <a href=\"/report?name=" +
       enc + "&amp;rev=HEAD\">Report of the archived configuration</a></p>";
  if (u.role == Role::operator_) {
    b += "<form method=\"post\" action=\"/backup\" class=\"inline\">" + csrf_field(u) +
         "<input type=\"hidden\" name=\"name\" value=\"" + esc(d.name) +
         "\"><button type=\"submit\" id=\"backup-now\">Back up now</button></form> "
         "<a class=\"button\" id=\"replace\" href=\"/replace?name=" +
         enc + "\">Replace the drive / restore a revision</a>";
  } else {
    b += "<p class=\"muted\">Signed in as a viewer: you can look at everything and change "
         "nothing.</p>";
  }
  b += "</section>\n";

  b += history_section(u, d, approved, history);
  b += "</section>\n";
  return frame(&u, signed_in, d.name, b);
}

std::string replace(const ConsoleUser& u, bool signed_in, const fleet::LineEntry& line,
                    const fleet::DriveEntry& d, const std::string& rev, const std::string& approved,
                    const Result<Json>& history) {
  char id[8];
  std::snprintf(id, sizeof id, "0x%02X", d.id);
  std::string b = "<p class=\"crumbs\"><a href=\"/\">Plant</a> / " + position_link(d.name) +
                  "</p>\n<h1>Replace the drive / restore a revision</h1>\n";
  b += "<ol class=\"flow\"><li aria-current=\"step\">Check the drive and plan</li><li>Review "
       "the plan</li><li>Confirm with a reason</li><li>Progress and verify</li></ol>\n";
  b += "<p>The new (or the present) drive must be connected on line <strong>" + esc(line.name) +
       "</strong> (" + esc(line.port) + ") with drive ID <strong>" + id +
       "</strong>. Planning reads it: nothing is written before you confirm.</p>\n";
  if (u.role != Role::operator_)
    return frame(&u, signed_in, "Restore " + d.name,
                 b + "<p class=\"problem\">Signed in as a viewer: planning and restoring need "
                     "role operator.</p>\n");
  if (!history.ok() || history->empty())
    return frame(
        &u, signed_in, "Restore " + d.name,
        b + "<p class=\"problem\">" +
            esc(history.ok() ? "the archive holds no file of " + d.name + " yet: back it up first"
                             : history.error().message) +
            "</p>\n");
  b += "<form method=\"post\" action=\"/plan\" class=\"card\">" + csrf_field(u) +
       "<input type=\"hidden\" name=\"name\" value=\"" + esc(d.name) +
       "\"><label for=\"rev\">Revision to restore</label><select id=\"rev\" name=\"rev\">";
  bool first = true;
  // Without a revision named: the approved one, else the newest.
  bool approved_listed = false;
  for (const auto& h : *history) approved_listed = approved_listed || str(h, "commit") == approved;
  const std::string want = !rev.empty() && rev != "HEAD" ? rev : approved_listed ? approved : "";
  for (const auto& h : *history) {
    const std::string c = str(h, "commit");
    const bool chosen = want.empty() ? first : c.rfind(want, 0) == 0;
    std::string marks = first ? " (newest)" : "";
    if (c == approved) marks += " (approved)";
    b += "<option value=\"" + esc(c) + "\"" + (chosen ? " selected" : "") + ">" +
         esc(str(h, "time")) + " " + esc(c.substr(0, 10)) + " " +
         esc(split_message(str(h, "message")).subject) + marks + "</option>";
    first = false;
  }
  b += "</select><button type=\"submit\" id=\"plan\">Check the drive and plan</button></form>\n";
  return frame(&u, signed_in, "Restore " + d.name, b);
}

namespace {

// A restore's outcome in words: green, amber (values left out, listed), or
// what went wrong, what the drive holds, and what happens next.
std::string restore_outcome(const ConsoleUser& u, const Json& j, const std::string& name) {
  const std::string state = str(j, "state");
  const std::string enc = esc(url_encode(name));
  std::string b;
  const bool skipped =
      j.contains("skipped") && member(j, "skipped").is_array() && !member(j, "skipped").empty();
  if (state == "failed") {
    b += help_html(words::restore_failure_help(j, name));
    if (j.value("retry_pending", false))
      b += "<p>The service tries this restore again by itself when the drive answers (before "
           "the line's next drift check). The position's page shows it and lets an operator "
           "cancel it.</p>";
    if (!name.empty() && u.role == Role::operator_)
      b += "<p><a class=\"button\" href=\"/replace?name=" + enc +
           "\">Plan the restore again</a> <a class=\"button\" href=\"/position?name=" + enc +
           "\">Open the position</a></p>";
  } else if (skipped) {
    b += "<div class=\"amber\" id=\"partial\"><p><strong>Restored, except " +
         std::to_string(member(j, "skipped").size()) +
         " value(s) this drive cannot take.</strong> The drive keeps its own values there, and "
         "the position stays in drift until someone approves this result or the drive "
         "changes.</p><ul id=\"skipped\">";
    for (const auto& v : member(j, "skipped"))
      if (v.is_string()) b += "<li>" + esc(words::plain(v.get<std::string>())) + "</li>";
    b += "</ul></div>";
  } else {
    b += "<p class=\"verdict\" id=\"verdict\">" +
         esc(str(j, "outcome") == "nothing to do" ? "Nothing to do: the drive already held this "
                                                    "configuration."
                                                  : "Restored and verified: the drive reads back "
                                                    "what was written.") +
         "</p>";
    b += kept_section(member(j, "kept"), "kept",
                      "Not written, by policy: the drive keeps its own values here, and the "
                      "position is ok with them.");
  }
  return b;
}

}  // namespace

std::string job(const ConsoleUser& u, bool signed_in, const Json& j, const std::string& name) {
  const std::string state = str(j, "state");
  const bool restore = str(j, "kind") == "restore";
  std::string b;
  if (!name.empty())
    b += "<p class=\"crumbs\"><a href=\"/\">Plant</a> / " + position_link(name) + "</p>\n";
  // A live read (the API's diff or plan that waited for its line) is a job too.
  const std::string kind = str(j, "kind");
  std::string title =
      restore ? "Restore" : (kind == "diff" ? "Live diff" : (kind == "plan" ? "Plan" : "Backup"));
  if (!name.empty()) title += " of " + name;
  b += "<h1>" + esc(title) + " <span class=\"muted\">(job " + esc(str(j, "id")) + ")</span></h1>\n";
  // While the job runs the script reloads this section; without it, the
  // page's own reload does the same.
  b += std::string("<section id=\"live\" aria-live=\"polite\"") +
       (state == "queued" || state == "running" ? " data-refresh=\"1\"" : "") + ">";
  const auto& pr = member(j, "progress");
  const auto total = pr.value("total", 0u), done = pr.value("done", 0u);
  static const std::map<std::string, std::string> kState = {{"queued", "waiting for the line"},
                                                            {"running", "running"},
                                                            {"done", "finished"},
                                                            {"failed", "failed"}};
  const auto shown = kState.count(state) ? kState.at(state) : state;
  b += "<p>State: <strong class=\"job-state\" data-state=\"" + esc(state) + "\">" + esc(shown) +
       "</strong>";
  if (member(j, "retry_of").is_string())
    b += " &middot; <span id=\"retry-of\">automatic retry of job " + esc(str(j, "retry_of")) +
         (member(j, "asked_by").is_string() ? " (asked by " + esc(str(j, "asked_by")) + ")" : "") +
         "</span>";
  else if (j.contains("who") && member(j, "who").is_string())
    b += ", asked by " + esc(str(j, "who"));
  b += "</p>";
  b += "<progress max=\"" + std::to_string(total ? total : 1) + "\" value=\"" +
       std::to_string(done) + "\">" + std::to_string(done) + " of " + std::to_string(total) +
       "</progress> " + std::to_string(done) + " of " + std::to_string(total) +
       (restore ? " step(s)" : " drive(s)") + (state == "failed" ? " before it stopped" : "");
  if (!str(pr, "step").empty())
    b += std::string(state == "failed" ? "<p>It stopped during: " : "<p>Now: ") +
         "<span id=\"now\">" + esc(words::progress(str(pr, "step"))) +
         "</span></p><details class=\"cli\"><summary>As the command line says it</summary><pre>" +
         esc(str(pr, "step")) + "</pre></details>";
  if (member(j, "outcome").is_string()) {
    if (restore) {
      b += restore_outcome(u, j, name);
    } else {
      const bool bad = state == "failed";
      b += "<p class=\"" + std::string(bad ? "problem" : "verdict") + "\" id=\"outcome\">" +
           esc(bad ? "The backup failed." : "Backup " + str(j, "outcome") + ".") + "</p>";
    }
    b += cli_details(str(j, "outcome") + ": " + str(j, "message"),
                     j.contains("exit_code") && member(j, "exit_code").is_number()
                         ? std::optional<int>(member(j, "exit_code").get<int>())
                         : std::nullopt);
  }
  if (restore && member(j, "commit").is_string())
    b += "<p>Recorded in the archive as commit <code id=\"commit\">" + esc(str(j, "commit")) +
         "</code>.</p>";
  if (j.contains("counts")) {
    b += "<ul class=\"counts\">";
    for (const auto& [k, v] : member(j, "counts").items())
      b += "<li>" + esc(k) + " <strong>" + v.dump() + "</strong></li>";
    b += "</ul>";
  }
  if (!restore && j.contains("commits") && !member(j, "commits").empty()) {
    b += "<p>Committed:</p><ul>";
    for (const auto& c : member(j, "commits"))
      b += "<li><code>" + esc(c.get<std::string>()) + "</code></li>";
    b += "</ul>";
  }
  if (j.contains("errors") && !member(j, "errors").empty()) {
    b += "<p class=\"problem\">Errors:</p><ul>";
    for (const auto& e : member(j, "errors")) b += "<li>" + esc(e.get<std::string>()) + "</li>";
    b += "</ul>";
  }
  b += "</section>\n";
  if (!name.empty())
    b += "<p><a href=\"/position?name=" + esc(url_encode(name)) + "\">Back to " + name_html(name) +
         "</a></p>\n";
  return frame(&u, signed_in, "Job " + str(j, "id"), b);
}

std::string failure(const ConsoleUser* u, bool signed_in, const std::string& title,
                    const words::Help& help, const std::string& cli_message, const Retry& retry,
                    const std::string& position) {
  std::string b = "<h1>" + esc(title) + "</h1>\n" + help_html(help);
  if (!retry.action.empty()) {
    if (retry.post && u) {
      b += "<form method=\"post\" action=\"" + esc(retry.action) + "\" class=\"inline\">" +
           csrf_field(*u);
      for (const auto& [k, v] : retry.fields)
        b += "<input type=\"hidden\" name=\"" + esc(k) + "\" value=\"" + esc(v) + "\">";
      b += "<button type=\"submit\" id=\"retry\">" + esc(retry.label) + "</button></form> ";
    } else if (!retry.post) {
      b += "<a class=\"button\" id=\"retry\" href=\"" + esc(retry.action) + "\">" +
           esc(retry.label) + "</a> ";
    }
  }
  if (!position.empty())
    b += "<a class=\"button\" href=\"/position?name=" + esc(url_encode(position)) +
         "\">Open the position</a> ";
  b += "<a class=\"button\" href=\"/\">Plant overview</a>\n" + cli_details(cli_message, {});
  return frame(u, signed_in, title, b);
}

std::string error(const ConsoleUser* u, bool signed_in, const std::string& title,
                  const std::string& message) {
  return frame(u, signed_in, title,
               "<h1>" + esc(title) + "</h1>\n<p class=\"problem\" role=\"alert\">" + esc(message) +
                   "</p>\n<p><a href=\"/\">Plant overview</a></p>\n");
}

}  // namespace lmcfg::serve::pages
