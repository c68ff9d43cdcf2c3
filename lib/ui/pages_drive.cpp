// The drive, job and plan pages of lmcfg ui (ui/pages.hpp).
#include <map>

#include "serve/console.hpp"
#include "serve/console_pages.hpp"
#include "serve/console_words.hpp"
#include "ui/pages.hpp"

namespace lmcfg::ui::pages {

namespace cp = serve::pages;
namespace words = serve::words;
using cp::esc;
using cp::member;
using cp::str;

namespace {

// Names of ports and files are long and unbroken ("/dev/serial/by-id/usb-FTDI_..."):
// shown where they may break anywhere, so that a 390 px page does not scroll sideways.
std::string long_name(const std::string& s) { return "<code class=\"wrap\">" + esc(s) + "</code>"; }

std::string key_link(const std::string& key, const std::string& text) {
  return "<a href=\"/drive?key=" + esc(serve::url_encode(key)) + "\">" + esc(text) + "</a>";
}

std::string identity_section(const Json& d) {
  const auto& l = member(d, "link");
  const auto& info = member(d, "info");
  char id[8];
  std::snprintf(id, sizeof id, "%02Xh", l.value("id", 0u) & 0xFFu);
  std::string b =
      "<section aria-labelledby=\"h-id\"><h2 id=\"h-id\">The drive</h2><dl "
      "class=\"facts\" id=\"identity\">";
  b += "<dt>Port</dt><dd><code class=\"wrap\">" + esc(str(l, "port")) + "</code></dd>";
  b += "<dt>MACID</dt><dd class=\"id\">" + std::string(id) + "</dd>";
  b += "<dt>Rate</dt><dd>" + std::to_string(l.value("baud", 0u)) + " baud, parity " +
       esc(str(l, "parity")) + ", checksum " + esc(str(l, "checksum")) + "</dd>";
  if (info.is_object()) {
    const auto& st = member(info, "state");
    b += "<dt>State</dt><dd id=\"state\">" +
         (st.is_object() ? esc(str(st, "name")) + " <span class=\"muted\">(state var " +
                               esc(str(st, "state_var_hex")) + "h)</span>"
                         : std::string("not reported")) +
         "</dd>";
    std::string err = str(info, "actual_error");
    if (err == "No Error") err.clear();  // the drive's own text for none (LinRS §14.1)
    b += "<dt>Error</dt><dd id=\"error\">" +
         (err.empty() ? std::string("none") : "<span class=\"problem\">" + esc(err) + "</span>") +
         "</dd>";
    const auto& sw = member(info, "status_word");
    if (sw.is_object() && member(sw, "bits").is_array()) {
      std::string bits;
      for (const auto& bit : member(sw, "bits"))
        if (bit.is_string()) bits += (bits.empty() ? "" : ", ") + bit.get<std::string>();
      b += "<dt>Status word</dt><dd>" + esc(bits.empty() ? "no bit set" : bits) + "</dd>";
    }
  }
  b += "<dt>Family, firmware</dt><dd>LinRS reads neither (LinRS §10): a backup records the "
       "drive's UPID set, and the database labels the values as an E1100's.</dd>";
  b += "</dl><p class=\"muted\">The same drive on the command line: <code class=\"wrap\" "
       "id=\"options\">lmcfg info " +
       esc(str(d, "options")) + "</code></p></section>\n";
  return b;
}

std::string file_options(const Json& backups) {
  std::string o;
  for (const auto& f : backups)
    if (f.is_string()) o += "<option>" + esc(f.get<std::string>()) + "</option>";
  return o;
}

// The other drives found, as "drive:KEY" (the desk reads both).
std::string drive_options(const Json& drives) {
  std::string o;
  for (const auto& k : drives)
    if (k.is_string())
      o += "<option value=\"drive:" + esc(k.get<std::string>()) + "\">the drive " +
           esc(k.get<std::string>()) + "</option>";
  return o.empty() ? o : "<optgroup label=\"Another drive found\">" + o + "</optgroup>";
}

// A file from this computer: kept in the folder, then compared or planned.
std::string upload_form(const std::string& key, const std::string& csrf) {
  return "<form method=\"post\" action=\"/upload\" enctype=\"multipart/form-data\" "
         "class=\"card\" id=\"upload-form\">" +
         csrf_input(csrf) + hidden("key", key) +
         "<label for=\"upload\">A configuration file from this computer (.json or "
         ".xml)</label><input type=\"file\" id=\"upload\" name=\"file\" "
         "accept=\".json,.xml\" required><p class=\"muted\">It is kept in the backup folder "
         "first (under its own name, or NAME-2 when the folder holds another file of that "
         "name).</p><button type=\"submit\" name=\"then\" value=\"compare\" "
         "id=\"upload-compare\">Compare the drive with it</button> <button type=\"submit\" "
         "name=\"then\" value=\"plan\" id=\"upload-plan\">Plan restoring it</button></form>";
}

std::string actions_section(const Json& d, const std::string& csrf) {
  const std::string key = str(d, "key");
  const auto& files = member(d, "files");
  const bool has_files = files.is_array() && !files.empty();
  std::string b = "<section aria-labelledby=\"h-do\"><h2 id=\"h-do\">What to do</h2>";
  if (member(d, "busy_job").is_string())
    b += "<p class=\"amber\" id=\"busy\">An operation runs on this port now: <a href=\"/job?id=" +
         esc(str(d, "busy_job")) + "\">see its progress</a>. The next one waits for it.</p>";
  b += "<form method=\"post\" action=\"/backup\" class=\"card\">" + csrf_input(csrf) +
       hidden("key", key) +
       "<p>Read the whole configuration into a file of the folder.</p><button type=\"submit\" "
       "id=\"backup\">Back up</button></form>";
  b += "<form method=\"post\" action=\"/compare\" class=\"card\">" + csrf_input(csrf) +
       hidden("key", key) +
       "<label for=\"against\">Compare the drive with</label><select id=\"against\" "
       "name=\"against\"><option value=\"defaults\">factory defaults</option>" +
       file_options(files) + drive_options(member(d, "drives")) +
       "</select><button type=\"submit\" id=\"compare\">Compare</button>"
       "</form>";
  b += upload_form(key, csrf);
  if (has_files)
    b += "<form method=\"post\" action=\"/plan\" class=\"card\">" + csrf_input(csrf) +
         hidden("key", key) +
         "<label for=\"file\">Restore a file onto this drive</label><select id=\"file\" "
         "name=\"file\">" +
         file_options(files) +
         "</select><p class=\"muted\">First a plan: nothing is written before you confirm "
         "it.</p><button type=\"submit\" id=\"plan\">Check the drive and plan</button></form>";
  b += "<form method=\"post\" action=\"/undo\" class=\"card\">" + csrf_input(csrf) +
       hidden("key", key) +
       "<p>Put back what the last write from this computer changed (its undo record).</p>"
       "<button type=\"submit\" id=\"undo\">Plan the undo</button></form>";
  return b + "</section>\n";
}

std::string backups_section(const Json& d, const std::string& folder) {
  const auto& backups = member(d, "backups");
  std::string b =
      "<section aria-labelledby=\"h-backups\"><h2 id=\"h-backups\">Backups of this "
      "drive</h2>";
  if (!backups.is_array() || backups.empty())
    return b + "<p id=\"no-backups\">None in <code class=\"wrap\">" + esc(folder) +
           "</code> yet.</p></section>\n";
  b += "<ul id=\"backups\">";
  for (const auto& f : backups) {
    if (!f.is_string()) continue;
    const std::string n = f.get<std::string>();
    b += "<li><a href=\"/files/" + esc(serve::url_encode(n)) + "\" download>" + esc(n) +
         "</a> (<a class=\"report\" href=\"/report?file=" + esc(serve::url_encode(n)) +
         "\">report</a>)</li>";
  }
  return b + "</ul><p class=\"muted\">In <code class=\"wrap\">" + esc(folder) +
         "</code>.</p></section>\n";
}

std::string journal_section(const Json& d) {
  const auto& journal = member(d, "journal");
  std::string b =
      "<section aria-labelledby=\"h-journal\"><h2 id=\"h-journal\">Writes to this "
      "drive from this computer</h2>";
  if (!str(d, "journal_error").empty())
    b += "<p class=\"problem\">" + esc(str(d, "journal_error")) + "</p>";
  if (!journal.is_array() || journal.empty())
    return b + "<p id=\"no-journal\">None.</p></section>\n";
  b += "<table id=\"journal\"><thead><tr><th scope=\"col\">When</th><th scope=\"col\">What</th>"
       "<th scope=\"col\">Who, why</th><th scope=\"col\">Outcome</th></tr></thead><tbody>";
  for (const auto& r : journal) {
    b += "<tr><td>" + cp::local_time(str(r, "time")) + "</td><td>" + esc(str(r, "command")) + " " +
         esc(str(r, "file")) + "</td><td>" + esc(str(r, "who")) + ": " + esc(str(r, "reason")) +
         "</td><td>" + esc(str(r, "outcome")) + "</td></tr>";
  }
  return b + "</tbody></table></section>\n";
}

std::string result_html(const Json& j) {
  const std::string kind = str(j, "kind");
  const auto& r = member(j, "result");
  std::string b;
  if (kind == "find" || kind == "connect") {
    const auto& found = member(r, "found");
    if (!found.is_array() || found.empty())
      return "<p class=\"problem\" id=\"outcome\">No drive answered on " + esc(str(j, "port")) +
             ".</p><p>What to check: power (LEDs), the cable and the adapter, the drive's ID "
             "switches, another program on the port.</p>";
    b += "<p class=\"verdict\" id=\"outcome\">Found " + std::to_string(found.size()) +
         " drive(s).</p><ul id=\"found\">";
    for (const auto& k : found)
      if (k.is_string())
        b += "<li><a href=\"/drive?key=" + esc(serve::url_encode(k.get<std::string>())) + "\">" +
             long_name(k.get<std::string>()) + "</a></li>";
    return b + "</ul>";
  }
  if (kind == "backup")
    return "<p class=\"verdict\" id=\"outcome\">Backed up into <a href=\"/files/" +
           esc(serve::url_encode(str(r, "file"))) + "\" download id=\"file\">" +
           esc(str(r, "file")) + "</a>.</p><p class=\"muted\"><code class=\"wrap\">" +
           esc(str(r, "path")) + "</code></p>";
  if (kind == "compare")
    return std::string("<p class=\"verdict\" id=\"outcome\">") +
           (r.value("identical", false)
                ? "Identical: the drive holds what it is compared with."
                : "The drive differs in " + std::to_string(r.value("differences", 0u)) +
                      " item(s).") +
           "</p>" +
           (str(r, "against") == "defaults"
                ? std::string()
                : "<p class=\"muted\">The drive's communication values and MACID are its own "
                  "and not compared (a restore keeps them).</p>") +
           "<p><a class=\"button\" id=\"diff-page\" href=\"/compare?job=" + esc(str(j, "id")) +
           "\">Open the comparison</a></p>" +
           "<details class=\"cli\"><summary>As the command line says it</summary><pre>" +
           esc(str(r, "text")) + "</pre></details>";
  if (kind == "plan")
    return "<p class=\"verdict\" id=\"outcome\">The plan is ready.</p><p><a class=\"button\" "
           "id=\"plan-page\" href=\"/plan?id=" +
           esc(str(r, "plan_id")) + "\">Review the plan</a></p>";
  // restore, undo
  const auto& skipped = member(r, "skipped");
  if (skipped.is_array() && !skipped.empty()) {
    b += "<div class=\"amber\" id=\"partial\"><p><strong>Restored, except " +
         std::to_string(skipped.size()) +
         " value(s) this drive cannot take.</strong> The drive keeps its own values "
         "there.</p><ul id=\"skipped\">";
    for (const auto& v : skipped)
      if (v.is_string()) b += "<li>" + esc(words::plain(v.get<std::string>())) + "</li>";
    b += "</ul></div>";
  } else {
    b += "<p class=\"verdict\" id=\"outcome\">" +
         esc(str(r, "outcome") == "nothing to do"
                 ? "Nothing to do: the drive already held this configuration."
                 : "Restored and verified: the drive reads back what was written.") +
         "</p>";
  }
  if (member(r, "undo_command").is_string())
    b += "<p class=\"muted\" id=\"undo-saved\">What it held before is kept as an undo record "
         "(the drive's page offers Undo; on the command line: <code class=\"wrap\">" +
         esc(str(r, "undo_command")) + "</code>).</p>";
  return b;
}

}  // namespace

std::string drive(const Json& d, const std::string& folder, const std::string& csrf) {
  const auto& l = member(d, "link");
  char id[8];
  std::snprintf(id, sizeof id, "%02Xh", l.value("id", 0u) & 0xFFu);
  std::string b = "<p class=\"crumbs\"><a href=\"/\">Drives</a></p>\n<h1>Drive " + std::string(id) +
                  " on " + long_name(str(l, "port")) + "</h1>\n";
  b += identity_section(d) + actions_section(d, csrf) + backups_section(d, folder) +
       journal_section(d);
  return frame("Drive " + str(d, "key"), b, csrf);
}

std::string job(const Json& j, const std::string& csrf) {
  const std::string state = str(j, "state");
  const std::string kind = str(j, "kind");
  const bool write = kind == "restore" || kind == "undo";
  std::string b = "<p class=\"crumbs\"><a href=\"/\">Drives</a>";
  if (!str(j, "drive").empty()) b += " / " + key_link(str(j, "drive"), "the drive");
  static const std::map<std::string, std::string> kTitle = {
      {"find", "Find drives"}, {"connect", "Connect"}, {"backup", "Back up"},
      {"compare", "Compare"},  {"plan", "Plan"},       {"restore", "Restore"},
      {"undo", "Undo"}};
  b += "</p>\n<h1>" + esc(kTitle.count(kind) ? kTitle.at(kind) : kind) + " on " +
       long_name(str(j, "port")) + " <span class=\"muted\">(job " + esc(str(j, "id")) +
       ")</span></h1>\n";
  b += std::string("<section id=\"live\" aria-live=\"polite\"") +
       (state == "running" ? " data-refresh=\"1\"" : "") + ">";
  b += "<p>State: <strong class=\"job-state\" data-state=\"" + esc(state) + "\">" +
       esc(state == "done" ? "finished" : state) + "</strong></p>";
  const auto& pr = member(j, "progress");
  const auto total = pr.value("total", 0u), done = pr.value("done", 0u);
  if (state == "running") {
    b += "<progress max=\"" + std::to_string(total ? total : 1) + "\" value=\"" +
         std::to_string(done) + "\">" + std::to_string(done) + " of " + std::to_string(total) +
         "</progress> " + std::to_string(done) + " of " + std::to_string(total);
    if (!str(pr, "step").empty()) b += "<p>Now: " + esc(words::plain(str(pr, "step"))) + "</p>";
    if (write)
      b += "<p class=\"muted\">Closing this tab does not stop the write; open the drive's page "
           "again to see it.</p>";
  } else if (state == "failed") {
    if (write) {
      b += cp::help_html(words::restore_failure_help(j, ""));
      b += "<p>To go on: plan the restore again from the drive's page (a restore run again "
           "converges), or on the command line <code class=\"wrap\">lmcfg restore FILE " +
           esc(str(j, "port")) + " ...</code>, which finishes what this one began.</p>";
    } else {
      b += cp::help_html(words::help_for(
          Error(words::errc_for_exit_code(j.value("exit_code", 0)), str(j, "message")), ""));
    }
    b += cp::cli_details(str(j, "message"), j.value("exit_code", 0));
  } else {
    b += result_html(j);
  }
  b += "</section>\n";
  (void)csrf;
  return frame("Job " + str(j, "id"), b, csrf);
}

std::string plan(const Json& p, const std::string& csrf) {
  const std::string key = str(p, "drive");
  std::string b =
      "<p class=\"crumbs\"><a href=\"/\">Drives</a> / " + key_link(key, "the drive") + "</p>\n";
  b += "<h1>" + std::string(p.value("undo", false) ? "Undo: put back " : "Restore ") +
       long_name(str(p, "file")) + " onto the drive</h1>\n";
  bool refused = false;
  const std::string verdict = words::verdict(p, refused);
  b += std::string("<p class=\"") + (refused ? "problem" : "verdict") + "\" id=\"verdict\">" +
       esc(verdict) + "</p>\n";
  b +=
      "<section aria-labelledby=\"h-link\"><h2 id=\"h-link\">The drive</h2><p>A drive answers on " +
      esc(str(p, "port")) + " with ID <span class=\"id\">" + esc(str(p, "id")) + "</span>. ";
  b += p.value("factory_fresh", false)
           ? "It is <strong id=\"factory-fresh\">factory-fresh</strong>.</p>"
           : "It is <strong id=\"factory-fresh\">not factory-fresh</strong>: it holds a "
             "configuration, which this restore overwrites.</p>";
  b += "<p>This plan is valid for " + std::to_string(p.value("expires_in_s", 0L) / 60) +
       " more minute(s); after that, plan again.</p></section>\n";
  const bool problems = !member(p, "problems").empty();
  const bool incompatible = !member(p, "incompatible").empty();
  b += cp::items_section("problems", "Problems (nothing can be written until they are resolved)",
                         member(p, "problems"), "problem");
  b += cp::items_section("incompatible", "Values this drive cannot take", member(p, "incompatible"),
                         "");
  b += "<section aria-labelledby=\"h-plan\"><h2 id=\"h-plan\">What will be written</h2>";
  b += p.value("nothing_to_do", false)
           ? "<p id=\"nothing-to-do\">Nothing to do: the drive already holds this "
             "configuration.</p>"
           : cp::steps_table(p);
  b += "</section>\n";
  b += cp::items_section("losses", "What the drive loses", member(p, "losses"), "");
  b += cp::items_section("notes", "Notes (what is kept, and why)", member(p, "notes"), "muted");
  b += "<section aria-labelledby=\"h-confirm\"><h2 id=\"h-confirm\">Confirm</h2>";
  if (problems) {
    b += "<p>Nothing can be written with this plan. Choose another file on the " +
         key_link(key, "drive's page") + ", or check that the right drive is connected.</p>";
  } else if (p.value("nothing_to_do", false) && !incompatible) {
    b += "<p>Nothing to write. " + key_link(key, "Back to the drive") + "</p>";
  } else {
    b += "<form method=\"post\" action=\"/execute\" class=\"card\" id=\"confirm\">" +
         csrf_input(csrf) + hidden("plan", str(p, "plan_id"));
    if (incompatible)
      b += "<label class=\"check\"><input type=\"checkbox\" name=\"skip_incompatible\" value=\"1\" "
           "id=\"skip-incompatible\" required> Restore everything else, without the " +
           std::to_string(member(p, "incompatible").size()) +
           " value(s) listed above. The drive keeps its own values there.</label>";
    b += "<label for=\"reason\">Reason (recorded in the journal)</label><input id=\"reason\" "
         "name=\"reason\" required maxlength=\"500\"><label for=\"ticket\">Ticket "
         "(optional)</label><input id=\"ticket\" name=\"ticket\" maxlength=\"100\">";
    b += std::string("<button type=\"submit\" class=\"danger\" id=\"execute\"") +
         (incompatible ? " data-needs=\"skip-incompatible\"" : "") +
         ">Write to the drive</button>"
         "</form>";
  }
  b += "</section>\n";
  std::string cli;
  for (const auto& st : member(p, "steps"))
    cli += esc(str(st, "kind") + ": " + str(st, "text")) + "\n";
  if (!cli.empty())
    b += "<details class=\"cli\"><summary>As the command line says it</summary><pre>" + cli +
         "</pre></details>\n";
  return frame("Plan", b, csrf);
}

}  // namespace lmcfg::ui::pages
