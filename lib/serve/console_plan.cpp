// The plan page (step 2 and 3 of "replace a drive / restore a revision"):
// the verdict first, in plain words; every write with the parameter's name
// and old and new values in units; refused plans without an active write
// button, with exactly what resolves them; the CLI's wording folded below.
#include <algorithm>

#include "serve/console_pages.hpp"

namespace lmcfg::serve::pages {

namespace {

std::string value_cell(const Json& st, const char* k) {
  if (!st.contains(k) || st[k].is_null()) return "<span class=\"muted\">not set</span>";
  const std::string unit = str(st, "unit");
  const std::string v = st[k].is_string() ? st[k].get<std::string>() : st[k].dump();
  // The display of lmcfg's plan already carries the unit where it scales a value.
  const bool has_unit = !unit.empty() && v.find(unit) != std::string::npos;
  return "<span class=\"value\">" + esc(v) + (unit.empty() || has_unit ? "" : " " + esc(unit)) +
         "</span>";
}

}  // namespace

std::string steps_table(const Json& p) {
  std::string b =
      "<table class=\"plan\"><thead><tr><th scope=\"col\">#</th><th "
      "scope=\"col\">What</th><th scope=\"col\">Now (drive)</th><th scope=\"col\"><span "
      "class=\"sr\">becomes</span></th><th scope=\"col\">After (configuration)</th></tr>"
      "</thead><tbody>\n";
  std::size_t n = 0;
  for (const auto& st : member(p, "steps")) {
    ++n;
    b += "<tr class=\"step\" data-kind=\"" + esc(str(st, "kind")) + "\"><td>" + std::to_string(n) +
         "</td>";
    if (st.contains("upid")) {
      const std::string name = str(st, "name");
      b += "<td><span class=\"pname\">" + esc(name.empty() ? "parameter" : name) +
           "</span> <span class=\"muted id\">" + esc(str(st, "upid")) +
           "h</span></td><td data-label=\"Now (drive)\">" + value_cell(st, "old") +
           "</td><td aria-hidden=\"true\">&rarr;</td><td data-label=\"After (configuration)\">" +
           value_cell(st, "new") + "</td>";
    } else {
      b += "<td colspan=\"4\">" + esc(words::step(st)) + "</td>";
    }
    b += "</tr>\n";
  }
  return b + "</tbody></table>\n";
}

std::string items_section(const char* id, const char* title, const Json& items, const char* cls) {
  if (!items.is_array() || items.empty()) return "";
  std::string b = "<section aria-labelledby=\"h-" + std::string(id) + "\"><h2 id=\"h-" + id +
                  "\">" + title + "</h2><ul class=\"" + cls + "\" id=\"" + id + "\">";
  for (const auto& it : items)
    b += "<li>" +
         esc(words::plain(it.is_string()                             ? it.get<std::string>()
                          : it.is_object() && it.contains("message") ? str(it, "message")
                                                                     : it.dump())) +
         "</li>";
  return b + "</ul></section>\n";
}

namespace {

// What resolves a refused plan: another revision, the drive read now (is the
// right one connected?), and, for values this drive cannot take, the restore
// without them with what that means.
std::string resolve_section(const ConsoleUser& u, const Json& p, bool problems, bool incompatible) {
  const std::string name = str(p, "drive");
  const std::string enc = esc(url_encode(name));
  std::string b = "<section aria-labelledby=\"h-confirm\"><h2 id=\"h-confirm\">";
  b += problems || incompatible ? "What you can do" : "Confirm";
  b += "</h2>";
  if (u.role != Role::operator_)
    return b + "<p class=\"muted\">Signed in as a viewer: restoring needs role operator.</p>" +
           "</section>\n";
  if (member(p, "executed_job").is_string()) {
    const std::string job = str(p, "executed_job");
    return b +
           "<p id=\"executed\">This plan was written to the drive already. <a "
           "class=\"button\" href=\"/job?id=" +
           esc(url_encode(job)) + "&amp;name=" + enc +
           "\">See how it went</a> <a class=\"button\" href=\"/replace?name=" + enc +
           "\">Plan again</a></p></section>\n";
  }
  if (p.value("nothing_to_do", false) && !incompatible && !problems)
    return b + "<p>Nothing to write. <a class=\"button\" href=\"/position?name=" + enc +
           "\">Back to the position</a> <a class=\"button\" href=\"/replace?name=" + enc +
           "\">Choose another revision</a></p></section>\n";
  if (problems) {
    b += "<p>Nothing can be written with this plan. To go on:</p><ul class=\"resolve\">"
         "<li><a class=\"button\" href=\"/replace?name=" +
         enc +
         "\">Choose another revision</a></li>"
         "<li><a class=\"button\" href=\"/diff?name=" +
         enc +
         "&amp;from=HEAD&amp;to=live\">Read the drive now</a> (is the right drive connected, "
         "and does it answer?)</li><li>Update the drive's firmware if a problem names it, then "
         "<a href=\"/replace?name=" +
         enc + "\">plan again</a>.</li></ul>";
    return b + "</section>\n";
  }
  b += "<form method=\"post\" action=\"/execute\" class=\"card\" id=\"confirm\">" + csrf_field(u) +
       "<input type=\"hidden\" name=\"plan\" value=\"" + esc(str(p, "plan_id")) +
       "\"><input type=\"hidden\" name=\"name\" value=\"" + esc(name) + "\">";
  if (incompatible) {
    // Required: without the box ticked the browser does not send the form,
    // and the service refuses the plan anyway.
    b += "<label class=\"check\"><input type=\"checkbox\" name=\"skip_incompatible\" value=\"1\" "
         "id=\"skip-incompatible\" required> Restore everything else, without the " +
         std::to_string(member(p, "incompatible").size()) +
         " value(s) listed above. The drive keeps its own values there, and the position stays "
         "in drift until someone approves the result.</label>";
  }
  b += "<label for=\"reason\">Reason (recorded in the archive)</label>"
       "<input id=\"reason\" name=\"reason\" required maxlength=\"500\">"
       "<label for=\"ticket\">Ticket (optional)</label><input id=\"ticket\" name=\"ticket\" "
       "maxlength=\"100\">";
  b += std::string("<button type=\"submit\" class=\"danger\" id=\"execute\"") +
       (incompatible ? " data-needs=\"skip-incompatible\"" : "") + ">" +
       (incompatible ? "Write the rest to the drive" : "Write to the drive") + "</button></form>";
  if (incompatible)
    b += "<p>Or <a href=\"/replace?name=" + enc +
         "\">choose another revision</a> that this drive can take.</p>";
  return b + "</section>\n";
}

}  // namespace

std::string kept_section(const Json& kept, const std::string& id, const std::string& intro) {
  if (!kept.is_array() || kept.empty()) return "";
  std::string b = "<section aria-labelledby=\"h-" + id + "\"><h2 id=\"h-" + id +
                  "\">What stays different</h2><p>" + esc(intro) + "</p><ul class=\"kept\" id=\"" +
                  id + "\">";
  std::vector<std::string> remedies;
  for (const auto& k : kept) {
    const std::string name = str(k, "name"), upid = str(k, "upid");
    b += "<li><span class=\"pname\">" + esc(name.empty() ? "parameter" : name) + "</span>" +
         (upid.empty() ? "" : " <span class=\"muted id\">" + esc(upid) + "h</span>") +
         ": the configuration holds <span class=\"value\">" + esc(str(k, "configuration")) +
         "</span>, the drive keeps <span class=\"value\">" + esc(str(k, "drive")) +
         "</span>. <span class=\"muted\">Why: " + esc(str(k, "reason")) + ".</span></li>";
    const std::string r = str(k, "remedy");
    if (!r.empty() && std::find(remedies.begin(), remedies.end(), r) == remedies.end())
      remedies.push_back(r);
  }
  b += "</ul>";
  for (const auto& r : remedies) b += "<p class=\"remedy\">" + esc(r) + "</p>";
  return b + "</section>\n";
}

std::string plan(const ConsoleUser& u, bool signed_in, const Json& p, TimePoint now) {
  const std::string name = str(p, "drive");
  std::string b = "<p class=\"crumbs\"><a href=\"/\">Plant</a> / " + position_link(name) +
                  "</p>\n<h1>Restore " + name_html(name) + "</h1>\n";
  b += "<ol class=\"flow\"><li>Check the drive and plan</li><li aria-current=\"step\">Review "
       "the plan</li><li aria-current=\"step\">Confirm with a reason</li><li>Progress and "
       "verify</li></ol>\n";
  bool refused = false;
  const std::string verdict = words::verdict(p, refused);
  b += std::string("<p class=\"") + (refused ? "problem" : "verdict") + "\" id=\"verdict\">" +
       esc(verdict) + "</p>\n";

  b += "<section aria-labelledby=\"h-link\"><h2 id=\"h-link\">The drive at this position</h2>";
  b += "<p class=\"link-ok\">A drive answers on line " + esc(str(p, "line")) +
       " with ID <span "
       "class=\"id\">" +
       esc(str(p, "id")) + "</span>. ";
  b += p.value("factory_fresh", false)
           ? "It is <strong id=\"factory-fresh\">factory-fresh</strong> (a replacement drive as "
             "it leaves the factory).</p>"
           : "It is <strong id=\"factory-fresh\">not factory-fresh</strong>: it holds a "
             "configuration, which this restore overwrites.</p>";
  b += "<p>Configuration: " + esc(str(p, "file")) + " (revision <code>" +
       esc(str(p, "commit").substr(0, 10)) + "</code>). This plan is valid until " +
       local_time(str(p, "expires")) + " (" + time_cell(str(p, "expires"), now) +
       "); after that, plan again.</p></section>\n";

  const bool problems = p.contains("problems") && !member(p, "problems").empty();
  const bool incompatible = p.contains("incompatible") && !member(p, "incompatible").empty();
  // What stops the plan comes before what it would do.
  b += items_section("problems", "Problems (nothing can be written until they are resolved)",
                     member(p, "problems"), "problem");
  b +=
      items_section("incompatible", "Values this drive cannot take", member(p, "incompatible"), "");

  b += "<section aria-labelledby=\"h-plan\"><h2 id=\"h-plan\">What will be written</h2>";
  if (p.value("nothing_to_do", false))
    b += "<p id=\"nothing-to-do\">Nothing to do: the drive already holds this configuration" +
         std::string(member(p, "kept").empty() ? "" : ", except the values it keeps (below)") +
         ".</p>";
  else
    b += steps_table(p);
  b += "</section>\n";
  b += kept_section(member(p, "kept"), "kept",
                    "The drive keeps these values of its own; they are not written, and the "
                    "position is ok with them afterwards.");
  b += items_section("losses", "What the drive loses", member(p, "losses"), "");
  // Notes in a technician's words; the CLI's wording folded below them.
  const Json& notes = member(p, "notes");
  if (notes.is_array() && !notes.empty()) {
    b += "<section aria-labelledby=\"h-notes\"><h2 id=\"h-notes\">Notes</h2><ul class=\"muted\" "
         "id=\"notes\">";
    std::string cli;
    for (const auto& n : notes) {
      const std::string t = n.is_string() ? n.get<std::string>() : n.dump();
      b += "<li>" + esc(words::note(t)) + "</li>";
      cli += esc(t) + "\n";
    }
    b += "</ul><details class=\"cli\"><summary>The notes as the command line says them</summary>"
         "<pre>" +
         cli + "</pre></details></section>\n";
  }
  b += resolve_section(u, p, problems, incompatible);

  // The CLI's plan, one click away: each step as `lmcfg restore --dry-run` names it.
  // (Each line escaped on its own: the escaping shows a control character,
  // a line break included, as \xNN.)
  std::string cli;
  for (const auto& st : member(p, "steps"))
    cli += esc(str(st, "kind") + ": " + str(st, "text")) + "\n";
  if (!cli.empty())
    b += "<details class=\"cli\"><summary>As the command line says it</summary><pre>" + cli +
         "</pre></details>\n";
  return frame(&u, signed_in, "Plan for " + name, b);
}

}  // namespace lmcfg::serve::pages
