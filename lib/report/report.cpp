// The HTML report's page (report/report.hpp): head and stylesheets, identity,
// the diff summary and scope, parameters per layer. Curves: report_curves.cpp;
// command table: report_ct.cpp.
#include "report/report.hpp"

#include <array>
#include <map>
#include <set>

#include "common/bytes.hpp"
#include "common/layers.hpp"
#include "db/database.hpp"
#include "db/value.hpp"
#include "ops/backup.hpp"
#include "ops/compare.hpp"
#include "ops/devicenet.hpp"
#include "report/report_parts.hpp"

namespace lmcfg::report {

// Values and scopes read as lmcfg diff and lmcfg get show them.
using ops::describe_scope;
using ops::devicenet_value_name;
using ops::devicenet_value_text;
using ops::display_value;
using ops::is_can_port;

std::string html_escape(std::string_view s) {
  std::string out;
  out.reserve(s.size() + 8);
  auto hex = [&](unsigned char c) {
    static const char* kHex = "0123456789ABCDEF";
    out += "\\x";
    out += kHex[c >> 4];
    out += kHex[c & 15];
  };
  for (std::size_t i = 0; i < s.size();) {
    const auto c = static_cast<unsigned char>(s[i]);
    if (c < 0x80) {
      switch (c) {
        case '&':
          out += "&amp;";
          break;
        case '<':
          out += "&lt;";
          break;
        case '>':
          out += "&gt;";
          break;
        case '"':
          out += "&quot;";
          break;
        case '\'':
          out += "&#39;";
          break;
        default:
          if (c < 0x20 || c == 0x7F)
            hex(c);
          else
            out += static_cast<char>(c);
      }
      ++i;
      continue;
    }
    // A well-formed UTF-8 sequence (no overlong forms, no surrogates) passes.
    std::size_t len = c >= 0xF0 && c <= 0xF4 ? 4 : c >= 0xE0 ? 3 : c >= 0xC2 && c <= 0xDF ? 2 : 0;
    if (c >= 0xF5) len = 0;
    bool ok = len > 0 && i + len <= s.size();
    for (std::size_t k = 1; ok && k < len; ++k)
      ok = (static_cast<unsigned char>(s[i + k]) & 0xC0) == 0x80;
    if (ok && len >= 3) {
      const auto c1 = static_cast<unsigned char>(s[i + 1]);
      if ((c == 0xE0 && c1 < 0xA0) || (c == 0xED && c1 >= 0xA0) || (c == 0xF0 && c1 < 0x90) ||
          (c == 0xF4 && c1 >= 0x90))
        ok = false;
    }
    if (!ok) {
      hex(c);
      ++i;
      continue;
    }
    out.append(s.substr(i, len));
    i += len;
  }
  return out;
}

namespace parts {

std::string diff_key(const DiffItem& it) {
  std::string key;
  switch (it.kind) {
    case DiffItem::Kind::parameter:
      key = hex(it.key, 4);
      break;
    case DiffItem::Kind::curve:
    case DiffItem::Kind::ct_entry:
      key = std::to_string(it.key);
      break;
    case DiffItem::Kind::devicenet:
      key = (it.motor == config::kDevicenetController
                 ? std::string("controller")
                 : std::string(1, static_cast<char>('A' + it.motor))) +
            "/" + hex(it.key, 2) + (it.live ? "/live" : "");
      break;
    default:
      key = html_escape(it.name);
  }
  std::string s =
      " data-kind=\"" + std::string(ops::kind_name(it.kind)) + "\" data-key=\"" + key + "\"";
  if (it.kind == DiffItem::Kind::parameter)
    s += " data-layer=\"" + std::string(lmcfg::layers::name(it.layer)) + "\"";
  return s;
}

}  // namespace parts

namespace {

using namespace parts;

constexpr const char* kStyle = R"css(
:root{--a:#1f5fbf;--b:#d9480f}
body{font:14px/1.4 system-ui,sans-serif;color:#1d1d1d;margin:0 auto;max-width:1280px;padding:0 1em 2em}
h1{font-size:1.5em;margin:.6em 0 .2em}h2{font-size:1.25em;border-bottom:2px solid #444;margin-top:1.6em}
p.meta{color:#555;margin:.2em 0 1em}
nav{position:sticky;top:0;background:#fff;border-bottom:1px solid #ccc;padding:.4em 0;z-index:1}
nav a{margin-right:1em}
table{border-collapse:collapse;margin:.4em 0}
table.params{table-layout:fixed;width:100%;margin:0}
table.params tr>:nth-child(1){width:5.5em}table.params tr>:nth-child(2){width:28%}
table.params tr>:nth-child(5),table.params tr>:nth-child(6){width:9em}
table.params.d tr>:nth-child(4){width:1.5em}table.params.d tr>:nth-child(5){width:auto}
table.params.chunk{margin:-1px 0 0;content-visibility:auto;contain-intrinsic-size:auto 2500px}
table.ct{content-visibility:auto;contain-intrinsic-size:auto 4000px}
table.params td{overflow-wrap:anywhere}
details,figure.curve{content-visibility:auto;contain-intrinsic-size:auto 600px}
th,td{border:1px solid #cfcfcf;padding:2px 6px;text-align:left;vertical-align:top}
thead th{background:#eee}
td.num,th.num{text-align:right}
tr.param td:first-child,tr.ct td:first-child{font-family:ui-monospace,monospace}
details>summary{cursor:pointer;font-weight:600;margin:.6em 0 .2em}
.mod{color:#8a4b00;font-weight:600}.same{color:#777}
tr.diff.changed>td,tr.diff:not(.added):not(.removed)>td{background:#fff3bf}
tr.diff.added>td{background:#d3f9d8}tr.diff.removed>td{background:#ffe3e3}
td.chg,tr.chg>td{background:#fff3bf;font-weight:600}
.arrow{color:#777;padding:0 .3em}.old{color:#a61e1e}.new{color:#0b6b21;font-weight:600}
.bad{color:#c92a2a}.absent{color:#888;font-style:italic}
.tag{font-size:.8em;padding:0 .4em;border-radius:3px;background:#e9b500;color:#000}
figure.curve{margin:1em 0;padding:.5em .8em;border:1px solid #d5d5d5;break-inside:avoid}
figure.curve.diff{border:2px solid #e9b500}
figcaption{font-weight:600;margin-bottom:.3em}
.fig{display:flex;flex-wrap:wrap;gap:1em;align-items:flex-start}
.fig>div{flex:1 1 560px;max-width:816px}
svg.plot{width:100%;max-width:816px;height:auto;display:block}
svg.plot .grid line{stroke:#e6e6e6;stroke-width:1}
svg.plot .frame{fill:none;stroke:#888}
svg.plot text{font-size:11px;fill:#333}
.tx,.xl,.yl{text-anchor:middle}.ty{text-anchor:end}
polyline{fill:none;stroke-width:12;stroke-linejoin:round}
polyline.a{stroke:var(--a)}polyline.b{stroke:var(--b);stroke-dasharray:40 20}
polyline.delta{stroke:#444}
.ka,.kb{display:inline-block;color:#fff;padding:0 .4em;border-radius:3px}
.ka{background:var(--a)}.kb{background:var(--b)}
table.info{font-size:.9em}
.summary td.num{font-weight:600}
input.toggle{margin-left:0}
#only-diff:checked~main tr.param:not(.diff),#only-diff:checked~main tr.ct:not(.diff),
#only-diff:checked~main figure.curve:not(.diff){display:none}
@media print{
 body{max-width:none;font-size:9.5pt;padding:0}
 nav,input.toggle,label.toggle{display:none}
 section.page{break-before:page}
 tr,figure.curve,table.info{break-inside:avoid}
 a{color:inherit;text-decoration:none}
 h2{break-after:avoid}
}
)css";

std::string layer_name(int l) { return std::string(lmcfg::layers::name(l)); }

// The database's entry, the name it or the capture knows.
struct ParamInfo {
  std::string name, type;
  std::optional<std::uint32_t> def;
};

ParamInfo param_info(const config::Parameter& p, const db::Database& db) {
  ParamInfo i;
  const db::Parameter* d = db.find(p.upid);
  i.name = d && !d->name.empty() ? d->name : p.name;
  i.def = ops::default_of(db, p.upid, p.default_value).value;
  if (p.type) {
    auto t = db::type_from_code(*p.type);
    i.type = t ? std::string(db::type_name(*t)) : "code " + std::to_string(*p.type);
  } else if (d && d->spec.type) {
    i.type = std::string(db::type_name(*d->spec.type));
  }
  return i;
}

std::string page_head(const std::string& title) {
  return "<!DOCTYPE html>\n<html lang=\"en\"><head><meta charset=\"utf-8\">"
         "<meta http-equiv=\"Content-Security-Policy\" content=\"default-src 'none'; "
         "style-src 'unsafe-inline'\">"
         "<meta name=\"viewport\" content=\"width=device-width, initial-scale=1\">"
         "<meta name=\"generator\" content=\"lmcfg report\"><title>" +
         html_escape(title) + "</title><style>" + kStyle + "</style></head><body>\n";
}

std::string meta_line(const ReportOptions& opt, const db::Database& db) {
  std::string s = "<p class=\"meta\">Report";
  if (!opt.tool_version.empty()) s += " by " + html_escape(opt.tool_version);
  if (!opt.generated_at.empty()) s += ", generated " + html_escape(opt.generated_at);
  s += "; UPID database: " +
       (!db.is_empty() ? html_escape(db.info().content_hash)
                       : std::string("none (values shown raw)")) +
       ".</p>\n";
  return s;
}

// Identity fields as (field, value): the names diff's metadata items use
// ("macid", "product", "firmware", "upid_fingerprint", "label KEY") first.
std::vector<std::pair<std::string, std::string>> identity_rows(const config::Identity& id,
                                                               const std::set<std::string>& keys) {
  std::vector<std::pair<std::string, std::string>> r = {
      {"macid", id.macid},
      {"product", id.product},
      {"firmware", id.firmware},
      {"upid_fingerprint", id.upid_fingerprint},
      {"captured_at", id.captured_at},
      {"link", id.link.port.empty() ? ""
               : is_can_port(id.link.port)
                   ? id.link.port + " (CAN) " + id.link.baud + " bit/s"
                   : id.link.port + " " + id.link.baud + " Bd, parity " + id.link.parity +
                         ", stop bits " + id.link.stop_bits + ", checksum " + id.link.checksum},
      {"tool_version", id.tool_version},
      {"upid_db_version", id.upid_db_version},
      {"upid_db_hash", id.upid_db_hash}};
  for (const auto& k : keys) {
    auto it = id.labels.find(k);
    r.push_back({"label " + k, it == id.labels.end() ? "" : it->second});
  }
  return r;
}

std::set<std::string> label_keys(const config::Identity& a, const config::Identity* b) {
  std::set<std::string> k;
  for (const auto& [key, v] : a.labels) k.insert(key);
  if (b)
    for (const auto& [key, v] : b->labels) k.insert(key);
  return k;
}

std::string nav(bool diff, bool devicenet) {
  std::string s = "<nav><a href=\"#identity\">Identity</a>";
  if (diff) s += "<a href=\"#summary\">Summary</a>";
  s += "<a href=\"#parameters\">Parameters</a><a href=\"#curves\">Curves</a>"
       "<a href=\"#command-table\">Command table</a>";
  if (devicenet) s += "<a href=\"#devicenet\">DeviceNet values</a>";
  s += "</nav>\n";
  return s;
}

std::string value_or_none(const std::string& v) {
  return v.empty() ? "<span class=\"absent\">(none)</span>" : html_escape(v);
}

// Long parameter tables are cut into tables of kChunk rows (the same fixed
// column widths, so they read as one): each is laid out only when it comes
// into view (content-visibility), not again for every block the parser adds.
constexpr std::size_t kChunk = 100;

// Called before each row; `n` counts the rows so far.
void chunk_break(std::string& rows, std::size_t& n, const char* cls) {
  if (n++ % kChunk == 0 && n > 1) {
    rows += "</tbody></table><table class=\"";
    rows += cls;
    rows += " chunk\"><tbody>\n";
  }
}

// ------------------------------------------------------------ one configuration

void params_single(std::string& out, const config::DriveConfig& cfg, const db::Database& db) {
  for (int l = 1; l <= lmcfg::layers::kCount; ++l) {
    const auto& ps = cfg.layer(l);
    if (!cfg.scope.layers[static_cast<std::size_t>(l - 1)]) {
      out += "<p>Layer " + layer_name(l) + ": not captured.</p>\n";
      continue;
    }
    std::size_t off_default = 0;
    std::string rows;
    std::size_t n = 0;
    for (const auto& p : ps) {
      chunk_break(rows, n, "params");
      const ParamInfo i = param_info(p, db);
      std::string mark = "<td class=\"same\">default unknown</td>";
      if (i.def) {
        const bool differs = *i.def != p.value;
        off_default += differs;
        mark = differs ? "<td class=\"mod\">\xE2\x89\xA0 default</td>"
                       : "<td class=\"same\">= default</td>";
      }
      rows += "<tr class=\"param\" data-layer=\"" + layer_name(l) + "\" data-upid=\"" +
              hex(p.upid, 4) + "\"><td>" + hex(p.upid, 4) + "h</td><td>" + html_escape(i.name) +
              "</td><td>" + html_escape(display_value(db, p.upid, p.value, p.type)) + "</td><td>" +
              (i.def ? html_escape(display_value(db, p.upid, *i.def, p.type))
                     : std::string("<span class=\"absent\">unknown</span>")) +
              "</td><td>" + html_escape(i.type) + "</td>" + mark + "</tr>\n";
    }
    out += "<details open><summary>Layer " + layer_name(l) + ": " + std::to_string(ps.size()) +
           " parameter(s) listed, " + std::to_string(off_default) +
           " differ from their default</summary>\n";
    if (ps.empty()) {
      out += "<p>No parameters listed.</p></details>\n";
      continue;
    }
    out +=
        "<table class=\"params\"><thead><tr><th>UPID</th><th>name</th><th>value</th>"
        "<th>factory default</th><th>type</th><th></th></tr></thead><tbody>\n" +
        rows + "</tbody></table></details>\n";
  }
}

// ------------------------------------------------------------ two configurations

using ByUpid = std::map<std::uint16_t, const config::Parameter*>;

ByUpid by_upid(const config::DriveConfig& c, int l) {
  ByUpid m;
  for (const auto& p : c.layer(l)) m.emplace(p.upid, &p);
  return m;
}

// A side's value of a parameter that has no DiffItem (the same on both sides,
// or not compared with --ignore-unit).
std::string side_value(const config::DriveConfig& c, int l, const config::Parameter* p,
                       const db::Database& db) {
  if (p) return display_value(db, p->upid, p->value, p->type);
  if (!c.scope.layers[static_cast<std::size_t>(l - 1)]) return "not captured";
  return c.scope.parameters == config::ParamSet::modified ? "default" : "absent";
}

const char* change_class(bool in_a, bool in_b) {
  return in_a && in_b ? "changed" : in_b ? "added" : "removed";
}

void params_diff(std::string& out, const config::DriveConfig& a, const config::DriveConfig& b,
                 const DiffResult& r, const db::Database& db) {
  std::map<std::pair<int, std::uint32_t>, const DiffItem*> items;
  for (const auto& it : r.items)
    if (it.kind == DiffItem::Kind::parameter) items[{it.layer, it.key}] = &it;
  for (int l = 1; l <= lmcfg::layers::kCount; ++l) {
    const auto la = by_upid(a, l), lb = by_upid(b, l);
    std::set<std::uint16_t> upids;
    for (const auto& [u, p] : la) upids.insert(u);
    for (const auto& [u, p] : lb) upids.insert(u);
    std::size_t differ = 0, n = 0;
    std::string rows;
    for (auto u : upids) {
      auto ia = la.find(u);
      auto ib = lb.find(u);
      const config::Parameter* pa = ia == la.end() ? nullptr : ia->second;
      const config::Parameter* pb = ib == lb.end() ? nullptr : ib->second;
      const ParamInfo info = param_info(pa ? *pa : *pb, db);
      auto found = items.find({l, u});
      const DiffItem* it = found == items.end() ? nullptr : found->second;
      std::string name = it && !it->name.empty() ? it->name : info.name;
      chunk_break(rows, n, "params d");
      rows += "<tr class=\"param";
      if (it) {
        ++differ;
        rows += std::string(" diff ") + change_class(pa, pb) + "\"" + diff_key(*it);
      } else {
        rows += "\"";
      }
      rows += " data-layer=\"" + layer_name(l) + "\" data-upid=\"" + hex(u, 4) + "\"><td>" +
              hex(u, 4) + "h</td><td>" + html_escape(name) + "</td>";
      if (it) {
        rows += "<td class=\"old\">" + html_escape(it->a) +
                "</td><td class=\"arrow\">\xE2\x86\x92</td><td class=\"new\">" +
                html_escape(it->b) + "</td><td>" + html_escape(it->detail) + "</td>";
      } else {
        const std::string va = side_value(a, l, pa, db), vb = side_value(b, l, pb, db);
        rows += "<td>" + html_escape(va) + "</td><td class=\"arrow\"></td><td>" + html_escape(vb) +
                "</td><td>" + (va != vb ? "not compared (per-unit)" : "") + "</td>";
      }
      rows += "</tr>\n";
    }
    const bool in_a = a.scope.layers[static_cast<std::size_t>(l - 1)];
    const bool in_b = b.scope.layers[static_cast<std::size_t>(l - 1)];
    out += "<details open><summary>Layer " + layer_name(l) + ": " + std::to_string(upids.size()) +
           " parameter(s) listed on either side, " + std::to_string(differ) + " differ" +
           (in_a && in_b ? ""
            : in_a       ? " (captured on side A only)"
            : in_b       ? " (captured on side B only)"
                         : " (not captured)") +
           "</summary>\n";
    if (upids.empty()) {
      out += "<p>No parameters listed.</p></details>\n";
      continue;
    }
    out +=
        "<table class=\"params d\"><thead><tr><th>UPID</th><th>name</th><th>A</th><th></th>"
        "<th>B</th><th>detail</th></tr></thead><tbody>\n" +
        rows + "</tbody></table></details>\n";
  }
}

void identity_diff(std::string& out, const config::DriveConfig& a, const config::DriveConfig& b,
                   const DiffResult& r) {
  std::map<std::string, const DiffItem*> meta;
  for (const auto& it : r.items)
    if (it.kind == DiffItem::Kind::metadata) meta[it.name] = &it;
  const auto keys = label_keys(a.identity, &b.identity);
  const auto ra = identity_rows(a.identity, keys), rb = identity_rows(b.identity, keys);
  out +=
      "<table class=\"identity\"><thead><tr><th>field</th><th>A</th><th>B</th></tr></thead>"
      "<tbody>\n";
  for (std::size_t i = 0; i < ra.size(); ++i) {
    auto it = meta.find(ra[i].first);
    const DiffItem* d = it == meta.end() ? nullptr : it->second;
    if (d) meta.erase(it);
    out += std::string("<tr") + (d ? " class=\"diff changed\"" + diff_key(*d) : "") + "><th>" +
           html_escape(ra[i].first) + "</th><td>" + value_or_none(ra[i].second) + "</td><td>" +
           value_or_none(rb[i].second) + "</td></tr>\n";
  }
  for (const auto& [name, d] : meta)  // any field diff compares that is not listed above
    out += "<tr class=\"diff changed\"" + diff_key(*d) + "><th>" + html_escape(name) + "</th><td>" +
           value_or_none(d->a) + "</td><td>" + value_or_none(d->b) + "</td></tr>\n";
  out += "</tbody></table>\n";
}

void summary(std::string& out, const config::DriveConfig& a, const config::DriveConfig& b,
             const DiffResult& r) {
  std::map<std::string, std::array<std::size_t, 3>> n;  // changed, added, removed
  std::array<ByUpid, lmcfg::layers::kCount> pa, pb;
  for (int l = 1; l <= lmcfg::layers::kCount; ++l) {
    pa[static_cast<std::size_t>(l - 1)] = by_upid(a, l);
    pb[static_cast<std::size_t>(l - 1)] = by_upid(b, l);
  }
  for (const auto& it : r.items) {
    bool in_a = true, in_b = true;
    if (it.kind == DiffItem::Kind::parameter) {
      const auto l = static_cast<std::size_t>(it.layer - 1);
      in_a = pa.at(l).count(static_cast<std::uint16_t>(it.key)) > 0;
      in_b = pb.at(l).count(static_cast<std::uint16_t>(it.key)) > 0;
    } else if (it.kind == DiffItem::Kind::curve) {
      in_a = a.find_curve(it.key), in_b = b.find_curve(it.key);
    } else if (it.kind == DiffItem::Kind::ct_entry) {
      in_a = a.find_ct_entry(it.key), in_b = b.find_ct_entry(it.key);
    } else if (it.kind == DiffItem::Kind::devicenet) {
      in_a = it.a != "absent", in_b = it.b != "absent";
    }
    ++n[ops::kind_name(it.kind)][in_a && in_b ? 0 : in_b ? 1 : 2];
  }
  out +=
      "<table class=\"summary\"><thead><tr><th>differences</th><th class=\"num\">changed</th>"
      "<th class=\"num\">added (B only)</th><th class=\"num\">removed (A only)</th></tr></thead>"
      "<tbody>\n";
  const std::pair<const char*, const char*> kinds[] = {{"metadata", "identity"},
                                                       {"scope", "scope (captured on one side)"},
                                                       {"parameter", "parameters"},
                                                       {"curve", "curves"},
                                                       {"ct_entry", "command table entries"},
                                                       {"devicenet", "DeviceNet values"}};
  for (const auto& [k, label] : kinds) {
    if (std::string_view(k) == "devicenet" && !r.devicenet_a && !r.devicenet_b) continue;
    const auto c = n[k];
    out += "<tr data-summary=\"" + std::string(k) + "\"><td>" + label + "</td>";
    for (auto v : c) out += "<td class=\"num\">" + std::to_string(v) + "</td>";
    out += "</tr>\n";
  }
  out += "</tbody></table>\n<p class=\"verdict\" data-differences=\"" +
         std::to_string(r.items.size()) + "\"><b>" +
         (r.identical() ? std::string("Identical")
                        : std::to_string(r.items.size()) + " difference(s)") +
         "</b>: <code>lmcfg diff</code> with the same options exits " +
         (r.identical() ? "0 (identical)" : "1 (different)") + ".</p>\n";
}

void scope_diff(std::string& out, const DiffResult& r) {
  out += "<table class=\"scope\"><tbody>\n<tr><th>A</th><td colspan=\"3\">" +
         html_escape(describe_scope(r.scope_a)) + "</td></tr>\n<tr><th>B</th><td colspan=\"3\">" +
         html_escape(describe_scope(r.scope_b)) +
         "</td></tr>\n<tr><th>compared</th><td colspan=\"3\">" +
         html_escape(describe_scope(r.compared)) + "</td></tr>\n";
  for (const auto& it : r.items)
    if (it.kind == DiffItem::Kind::scope)
      out += "<tr class=\"diff changed\"" + diff_key(it) + "><th>" + html_escape(it.name) +
             "</th><td>" + html_escape(it.a) + "</td><td>" + html_escape(it.b) + "</td><td>" +
             html_escape(it.detail) + "</td></tr>\n";
  out += "</tbody></table>\n";
  if (!r.notes.empty()) {
    out += "<ul class=\"notes\">";
    for (const auto& n : r.notes) out += "<li>" + html_escape(n) + "</li>";
    out += "</ul>\n";
  }
}

void curves_diff(std::string& out, const config::DriveConfig& a, const config::DriveConfig& b,
                 const DiffResult& r) {
  std::map<std::uint32_t, const DiffItem*> items;
  for (const auto& it : r.items)
    if (it.kind == DiffItem::Kind::curve) items[it.key] = &it;
  std::set<std::uint32_t> ids;
  for (const auto& c : a.curves) ids.insert(c.id);
  for (const auto& c : b.curves) ids.insert(c.id);
  if (!a.scope.curves || !b.scope.curves)
    out += std::string("<p>Curves captured on ") +
           (a.scope.curves   ? "side A only"
            : b.scope.curves ? "side B only"
                             : "neither side") +
           ".</p>\n";
  if (ids.empty()) out += "<p>No curves.</p>\n";
  for (auto id : ids) {
    auto it = items.find(id);
    curve_figure_diff(out, a.find_curve(id), b.find_curve(id),
                      it == items.end() ? nullptr : it->second);
  }
}

// The DeviceNet values that differ (seed 000 captures have no layers, curves
// or command table for the sections above to show).
void devicenet_diff(std::string& out, const DiffResult& r) {
  std::string rows;
  for (const auto& it : r.items)
    if (it.kind == DiffItem::Kind::devicenet)
      rows += std::string("<tr class=\"diff ") + change_class(it.a != "absent", it.b != "absent") +
              "\"" + diff_key(it) + "><td>" + html_escape(it.name) + (it.live ? " (live)" : "") +
              "</td><td class=\"old\">" + html_escape(it.a) +
              "</td><td class=\"arrow\">\xE2\x86\x92</td><td class=\"new\">" + html_escape(it.b) +
              "</td></tr>\n";
  if (rows.empty()) {
    out += "<p>No DeviceNet value differs.</p>\n";
    return;
  }
  out +=
      "<table class=\"devicenet\"><thead><tr><th>value</th><th>A</th><th></th><th>B</th></tr>"
      "</thead><tbody>\n" +
      rows + "</tbody></table>\n";
}

// A DeviceNet capture's section: its bit rate, IO modules and motors, then
// every value (live values marked: informational, never restored).
void devicenet_single(std::string& out, const config::DevicenetSection& dn,
                      const db::Database& db) {
  std::string motors, modules;
  for (int m : dn.motors)
    motors += (motors.empty() ? "" : ", ") + std::string(1, static_cast<char>('A' + m));
  for (const auto& m : dn.io_modules) modules += (modules.empty() ? "" : ", ") + m;
  out += "<table class=\"identity\"><tbody>\n<tr><th>CAN bit rate</th><td>" +
         std::to_string(dn.can_bitrate) + "</td></tr>\n<tr><th>IO modules</th><td>" +
         value_or_none(modules) + "</td></tr>\n<tr><th>motors</th><td>" + value_or_none(motors) +
         "</td></tr>\n</tbody></table>\n";
  if (dn.values.empty() && dn.live.empty()) {
    out += "<p>No values.</p>\n";
    return;
  }
  out +=
      "<table class=\"devicenet\"><thead><tr><th>value</th><th>read</th><th>kind</th></tr></thead>"
      "<tbody>\n";
  for (const bool live : {false, true})
    for (const auto& v : live ? dn.live : dn.values)
      out += "<tr><td>" + html_escape(devicenet_value_name(db, v)) + "</td><td>" +
             html_escape(devicenet_value_text(db, v)) + "</td><td>" +
             (live ? "live (not restored)" : "") + "</td></tr>\n";
  out += "</tbody></table>\n";
}

std::string section(const char* id, const char* title) {
  return std::string("<section class=\"page\" id=\"") + id + "\"><h2>" + title + "</h2>\n";
}

}  // namespace

std::string render_report(const config::DriveConfig& cfg, const std::string& name,
                          const db::Database& db, const ReportOptions& opt) {
  std::string out;
  out.reserve(4096 + cfg.curves.size() * 12000 +
              200 * (cfg.layers[0].size() + cfg.layers[1].size() + cfg.layers[2].size() +
                     cfg.layers[3].size()));
  out += page_head("lmcfg report: " + name);
  out += curve_defs();
  out += "<h1>Drive configuration: " + html_escape(name) + "</h1>\n" + meta_line(opt, db) +
         nav(false, cfg.devicenet.has_value()) + "<main>\n";
  out += section("identity", "Identity");
  out += "<table class=\"identity\"><tbody>\n";
  for (const auto& [k, v] : identity_rows(cfg.identity, label_keys(cfg.identity, nullptr)))
    out += "<tr><th>" + html_escape(k) + "</th><td>" + value_or_none(v) + "</td></tr>\n";
  out += "<tr><th>scope</th><td>" + html_escape(describe_scope(cfg.scope)) +
         "</td></tr>\n</tbody></table>\n</section>\n";
  out += section("parameters", "Parameters");
  params_single(out, cfg, db);
  out += "</section>\n" + section("curves", "Curves");
  if (!cfg.scope.curves)
    out += "<p>The curves were not captured.</p>\n";
  else if (cfg.curves.empty())
    out += "<p>No curves.</p>\n";
  for (const auto& c : cfg.curves) curve_figure(out, c);
  out += "</section>\n" + section("command-table", "Command table");
  ct_section(out, cfg, db);
  out += "</section>\n";
  if (cfg.devicenet) {
    out += section("devicenet", "DeviceNet values");
    devicenet_single(out, *cfg.devicenet, db);
    out += "</section>\n";
  }
  out += "</main></body></html>\n";
  return out;
}

std::string render_diff_report(const config::DriveConfig& a, const std::string& a_name,
                               const config::DriveConfig& b, const std::string& b_name,
                               const DiffResult& r, const db::Database& db,
                               const ReportOptions& opt) {
  std::string out;
  out.reserve(8192 + (a.curves.size() + b.curves.size()) * 12000);
  out += page_head("lmcfg diff report: " + a_name + " vs " + b_name);
  out += curve_defs();
  out += "<h1>Configuration diff: <span class=\"ka\">A</span> " + html_escape(a_name) +
         " \xE2\x86\x92 <span class=\"kb\">B</span> " + html_escape(b_name) + "</h1>\n" +
         meta_line(opt, db) + nav(true, r.devicenet_a || r.devicenet_b) +
         "<input class=\"toggle\" type=\"checkbox\" id=\"only-diff\"" +
         (opt.only_differences ? " checked" : "") +
         "><label class=\"toggle\" for=\"only-diff\"> show only the differences</label>\n<main>\n";
  out += section("summary", "Summary");
  summary(out, a, b, r);
  scope_diff(out, r);
  out += "</section>\n" + section("identity", "Identity");
  identity_diff(out, a, b, r);
  out += "</section>\n" + section("parameters", "Parameters");
  params_diff(out, a, b, r, db);
  out += "</section>\n" + section("curves", "Curves");
  curves_diff(out, a, b, r);
  out += "</section>\n" + section("command-table", "Command table");
  ct_section_diff(out, a, b, r, db);
  out += "</section>\n";
  if (r.devicenet_a || r.devicenet_b) {
    out += section("devicenet", "DeviceNet values");
    devicenet_diff(out, r);
    out += "</section>\n";
  }
  out += "</main></body></html>\n";
  return out;
}

}  // namespace lmcfg::report
