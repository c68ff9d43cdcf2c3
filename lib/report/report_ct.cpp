// Command table of the HTML report (report/report.hpp): one row per entry with
// its name, the motion command decoded through the database's catalogue
// (parameters with units), the link to the next entry as an in-page link, and
// the chains the links form; in a diff, A and B side by side with the fields
// that differ marked.
#include <map>
#include <set>
#include <vector>

#include "db/ct_entry.hpp"
#include "db/database.hpp"
#include "report/report.hpp"
#include "report/report_parts.hpp"

namespace lmcfg::report::parts {
namespace {

constexpr int kNoLink = -1;

struct EntryText {
  std::string name, command;
  std::vector<std::string> params;  // "Target Position 100 mm"
  int link = kNoLink;
};

EntryText entry_text(const config::CtEntry& e, const db::Database& db) {
  EntryText t;
  t.name = config::ct_entry_name(e.raw);
  if (e.raw.size() >= 4) {
    const unsigned link = e.raw[2] | (e.raw[3] << 8);
    if (link != db::kCtNoLink) t.link = static_cast<int>(link);
  }
  if (db.is_empty()) {
    t.command = "not decoded (no UPID database)";
    return t;
  }
  auto d = db::decode_ct_entry(db, e.raw);
  if (!d.ok()) {
    t.command = "not decoded: " + d.error().message;
    return t;
  }
  t.command = d->command_name;
  for (const auto& p : d->params)
    t.params.push_back((p.name.empty() ? "parameter " + std::to_string(p.index) : p.name) + " " +
                       p.text);
  return t;
}

std::string link_cell(int link, const std::set<std::uint32_t>& defined) {
  if (link == kNoLink) return "\xE2\x80\x94";  // em dash: none
  const std::string id = std::to_string(link);
  if (!defined.count(static_cast<std::uint32_t>(link)))
    return "\xE2\x86\x92 " + id + " <span class=\"bad\">(not defined)</span>";
  return "\xE2\x86\x92 <a href=\"#ct-" + id + "\">" + id + "</a>";
}

std::string params_cell(const std::vector<std::string>& p) {
  std::string s;
  for (const auto& x : p) s += (s.empty() ? "" : "<br>") + html_escape(x);
  return s;
}

// The chains the links form: from each entry no other entry links to, then
// from the smallest entry of each remaining cycle; every entry appears once.
std::vector<std::string> chains(const std::map<std::uint32_t, int>& links) {
  std::set<std::uint32_t> targets;
  for (const auto& [id, link] : links)
    if (link != kNoLink && static_cast<std::uint32_t>(link) != id)
      targets.insert(static_cast<std::uint32_t>(link));
  std::set<std::uint32_t> seen;
  std::vector<std::string> out;
  auto walk = [&](std::uint32_t start) {
    std::string s;
    std::uint32_t id = start;
    std::size_t n = 0;
    while (true) {
      seen.insert(id);
      s += (n++ ? " \xE2\x86\x92 " : "") + std::string("<a href=\"#ct-") + std::to_string(id) +
           "\">" + std::to_string(id) + "</a>";
      const int link = links.at(id);
      if (link == kNoLink) break;
      const auto next = static_cast<std::uint32_t>(link);
      if (!links.count(next)) {
        s += " \xE2\x86\x92 " + std::to_string(next) + " <span class=\"bad\">(not defined)</span>";
        break;
      }
      if (seen.count(next)) {
        s += " \xE2\x86\xBA " + std::to_string(next);  // loops back
        break;
      }
      id = next;
    }
    if (n > 1 || links.at(start) != kNoLink) out.push_back(s);
  };
  for (const auto& [id, link] : links)
    if (!targets.count(id) && !seen.count(id)) walk(id);
  for (const auto& [id, link] : links)
    if (!seen.count(id)) walk(id);
  return out;
}

void chains_block(std::string& out, const config::DriveConfig& cfg, const db::Database& db,
                  const char* side) {
  std::map<std::uint32_t, int> links;
  for (const auto& e : cfg.ct_entries) links[e.id] = entry_text(e, db).link;
  const auto c = chains(links);
  out += "<p class=\"chains\"><b>Linked entries";
  out += side;
  out += ":</b> ";
  if (c.empty()) out += "none";
  for (std::size_t i = 0; i < c.size(); ++i) out += (i ? "; " : "") + c[i];
  out += "</p>\n";
}

std::set<std::uint32_t> ids_of(const config::DriveConfig& c) {
  std::set<std::uint32_t> s;
  for (const auto& e : c.ct_entries) s.insert(e.id);
  return s;
}

}  // namespace

void ct_section(std::string& out, const config::DriveConfig& cfg, const db::Database& db) {
  if (!cfg.scope.command_table) {
    out += "<p>The command table was not captured.</p>\n";
    return;
  }
  if (cfg.ct_entries.empty()) {
    out += "<p>No command table entries.</p>\n";
    return;
  }
  chains_block(out, cfg, db, "");
  const auto defined = ids_of(cfg);
  out +=
      "<table class=\"ct\"><thead><tr><th>ID</th><th>name</th><th>motion command</th>"
      "<th>parameters</th><th>next</th></tr></thead><tbody>\n";
  for (const auto& e : cfg.ct_entries) {
    const EntryText t = entry_text(e, db);
    const std::string id = std::to_string(e.id);
    out += "<tr class=\"ct\" id=\"ct-" + id + "\" data-ct-id=\"" + id + "\"><td>" + id +
           "</td><td>" + html_escape(t.name) + "</td><td>" + html_escape(t.command) + "</td><td>" +
           params_cell(t.params) + "</td><td>" + link_cell(t.link, defined) + "</td></tr>\n";
  }
  out += "</tbody></table>\n";
}

void ct_section_diff(std::string& out, const config::DriveConfig& a, const config::DriveConfig& b,
                     const DiffResult& r, const db::Database& db) {
  if (!a.scope.command_table && !b.scope.command_table) {
    out += "<p>The command table was captured on neither side.</p>\n";
    return;
  }
  std::map<std::uint32_t, const DiffItem*> items;
  for (const auto& it : r.items)
    if (it.kind == DiffItem::Kind::ct_entry) items[it.key] = &it;
  const auto da = ids_of(a), dbs = ids_of(b);
  std::set<std::uint32_t> ids = da;
  ids.insert(dbs.begin(), dbs.end());
  if (ids.empty()) {
    out += "<p>No command table entries on either side.</p>\n";
    return;
  }
  if (a.scope.command_table) chains_block(out, a, db, " (A)");
  if (b.scope.command_table) chains_block(out, b, db, " (B)");
  out +=
      "<table class=\"ct side\"><thead><tr><th rowspan=\"2\">ID</th><th colspan=\"4\">A</th>"
      "<th colspan=\"4\">B</th></tr><tr><th>name</th><th>motion command</th><th>parameters</th>"
      "<th>next</th><th>name</th><th>motion command</th><th>parameters</th><th>next</th></tr>"
      "</thead><tbody>\n";
  for (auto id : ids) {
    const auto* ea = a.find_ct_entry(id);
    const auto* eb = b.find_ct_entry(id);
    const DiffItem* item = items.count(id) ? items[id] : nullptr;
    std::optional<EntryText> ta, tb;
    if (ea) ta = entry_text(*ea, db);
    if (eb) tb = entry_text(*eb, db);
    const std::string sid = std::to_string(id);
    std::string cls = "ct";
    if (item) cls += std::string(" diff ") + (!ea ? "added" : !eb ? "removed" : "changed");
    out += "<tr class=\"" + cls + "\" id=\"ct-" + sid + "\" data-ct-id=\"" + sid + "\"" +
           (item ? diff_key(*item) : "") + "><td>" + sid + "</td>";
    // Field by field; a field that differs from the other side is marked.
    auto cells = [&](const std::optional<EntryText>& t, const std::optional<EntryText>& other,
                     const std::set<std::uint32_t>& defined) {
      if (!t) {
        out += "<td colspan=\"4\" class=\"absent\">absent</td>";
        return;
      }
      const bool o = other.has_value();
      auto mark = [](bool differs) { return differs ? " class=\"chg\"" : ""; };
      out += std::string("<td") + mark(o && t->name != other->name) + ">" + html_escape(t->name) +
             "</td><td" + mark(o && t->command != other->command) + ">" + html_escape(t->command) +
             "</td><td" + mark(o && t->params != other->params) + ">" + params_cell(t->params) +
             "</td><td" + mark(o && t->link != other->link) + ">" + link_cell(t->link, defined) +
             "</td>";
    };
    cells(ta, tb, da);
    cells(tb, ta, dbs);
    out += "</tr>\n";
    if (item && !item->detail.empty())
      out += "<tr class=\"detail\"><td></td><td colspan=\"8\">" + html_escape(item->detail) +
             "</td></tr>\n";
  }
  out += "</tbody></table>\n";
}

}  // namespace lmcfg::report::parts
