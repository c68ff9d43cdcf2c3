// The console's stylesheet and script, embedded in the binary as the report
// embeds its style (lib/report/report.cpp): served by lmcfg itself, nothing
// from a CDN, no font, no framework.
#include "serve/console.hpp"

namespace lmcfg::serve {

namespace {

constexpr const char* kStyle = R"css(
:root { --fg: #1b1f24; --muted: #5a6470; --line: #d0d7de; --bg: #fff; --accent: #0b57d0;
  --ok: #1a7f37; --drift: #9a6700; --failed: #cf222e; --replaced: #8250df; --unknown: #57606a; }
* { box-sizing: border-box; }
body { margin: 0; font: 15px/1.45 system-ui, -apple-system, "Segoe UI", sans-serif; color: var(--fg);
  background: var(--bg); }
header { background: #24292f; color: #fff; }
header nav { display: flex; flex-wrap: wrap; align-items: center; gap: .25rem 1rem;
  max-width: 1200px; margin: 0 auto; padding: .5rem 1rem; }
header a, header .who { color: #fff; }
header .brand { font-weight: 600; text-decoration: none; margin-right: auto; }
main { max-width: 1200px; margin: 0 auto; padding: 1rem; }
h1 { font-size: 1.5rem; margin: .5rem 0 1rem; }
h2 { font-size: 1.15rem; margin: 1.5rem 0 .5rem; border-bottom: 1px solid var(--line); }
a { color: var(--accent); }
:focus-visible { outline: 3px solid #fb8c00; outline-offset: 2px; }
.skip { position: absolute; left: -999px; top: 0; background: #fff; padding: .5rem; z-index: 2; }
.skip:focus { left: 0; }
.muted { color: var(--muted); }
.problem { color: var(--failed); font-weight: 600; }
.crumbs { margin: 0; color: var(--muted); }
table { border-collapse: collapse; width: 100%; }
th, td { text-align: left; padding: .35rem .5rem; border-bottom: 1px solid var(--line);
  vertical-align: top; overflow-wrap: normal; word-break: normal; }
/* Names and IDs never break inside a word: a name only after its '/' (<wbr>). */
.name, .id, .pname, code, time, .status { white-space: nowrap; }
code.wrap { white-space: pre-wrap; overflow-wrap: anywhere; }
.sr { position: absolute; width: 1px; height: 1px; overflow: hidden; clip: rect(0 0 0 0); }
thead th { background: #f6f8fa; }
.status { display: inline-block; padding: 0 .5rem; border-radius: 1rem; color: #fff;
  font-size: .85rem; font-weight: 600; white-space: nowrap; background: var(--unknown); }
.s-ok { background: var(--ok); } .s-drift { background: var(--drift); }
.s-failed { background: var(--failed); } .s-replaced { background: var(--replaced); }
.s-never-backed-up { background: #fff; color: var(--fg); border: 1px solid var(--line); }
ul.counts { display: flex; flex-wrap: wrap; gap: .5rem 1.5rem; list-style: none; padding: 0; }
form.filters, form.card { display: flex; flex-wrap: wrap; gap: .5rem; align-items: center;
  margin: 1rem 0; }
form.card { flex-direction: column; align-items: stretch; max-width: 28rem; }
form.inline { display: inline; }
button, select, input, textarea { font: inherit; padding: .3rem .6rem; min-height: 40px;
  max-width: 100%; }
/* Touch targets of at least 40 px: buttons, fields, and the links people tap. */
a.button, td a, .links a, .crumbs a, nav a, details > summary, ol.timeline a {
  display: inline-block; min-height: 40px; padding-top: .55rem; padding-bottom: .55rem; }
label.check { display: flex; gap: .6rem; align-items: flex-start; min-height: 40px; }
label.check input { width: 24px; height: 24px; min-height: 24px; margin: 0; flex: none; }
.amber { background: #fff8c5; border-left: 4px solid var(--drift); padding: .25rem 1rem;
  margin: .75rem 0; }
.banner { position: sticky; top: 0; z-index: 3; background: var(--failed); color: #fff;
  padding: .6rem 1rem; font-weight: 600; }
ol.checklist li { margin: .25rem 0; }
ul.resolve { list-style: none; padding: 0; } ul.resolve li { margin: .5rem 0; }
details.cli { margin: 1rem 0; color: var(--muted); }
/* The CLI's wording keeps its lines, but never wider than the page. */
pre { white-space: pre-wrap; overflow-wrap: anywhere; }
button:disabled, button.danger:disabled { background: #8c959f; cursor: not-allowed; }
button { background: var(--accent); color: #fff; border: 0; border-radius: 4px; cursor: pointer; }
header button { background: #57606a; }
button.danger { background: var(--failed); }
a.button { display: inline-block; background: #fff; color: var(--accent); border: 1px solid var(--accent);
  border-radius: 4px; padding: .25rem .6rem; text-decoration: none; margin-left: .5rem; }
ol.flow { display: flex; flex-wrap: wrap; gap: .25rem 2.5rem; padding-left: 0;
  list-style-position: inside; color: var(--muted); }
ol.flow li[aria-current] { color: var(--fg); font-weight: 600; }
.verdict { color: var(--ok); font-weight: 600; }
.links { margin: .2rem 0 0; font-size: .9rem; }
table.plan td:nth-child(4) { color: var(--muted); }
dl.identity, dl.trailers { display: grid; grid-template-columns: max-content minmax(0, 1fr);
  gap: .2rem 1rem; }
dl.trailers { margin: .25rem 0 0 1rem; }
dt { font-weight: 600; } dd { margin: 0; overflow-wrap: anywhere; }
ul.kept li { margin: .25rem 0; } .value { overflow-wrap: anywhere; }
ol.timeline { list-style: none; padding: 0; border-left: 3px solid var(--line); }
ol.timeline li { margin: 0 0 .75rem; padding-left: .75rem; }
progress { width: 20rem; max-width: 100%; }
@media (max-width: 900px) {
  main { padding: .5rem; }
  table.positions th:nth-child(3), table.positions td:nth-child(3) { display: none; }
}
/* A phone held upright (390 px): the positions and the plan's steps as one
   card per row, each cell labelled, so no page scrolls sideways. */
@media (max-width: 600px) {
  table.positions thead, table.plan thead { position: absolute; width: 1px; height: 1px;
    overflow: hidden; clip: rect(0 0 0 0); }
  table.positions, table.positions tbody, table.positions tr, table.positions td,
  table.plan, table.plan tbody, table.plan tr, table.plan td { display: block; }
  table.positions tr, table.plan tr { border-bottom: 1px solid var(--line); padding: .35rem 0; }
  table.positions td, table.plan td { border: 0; padding: .1rem .25rem; }
  table.positions td[data-label]::before, table.plan td[data-label]::before {
    content: attr(data-label) ": "; color: var(--muted); }
  table.plan td[aria-hidden] { display: none; }
  ol.flow { gap: .25rem 1rem; }
  a.button { margin: .25rem .5rem .25rem 0; }
}
@media print {
  header, form, .skip { display: none; }
  a { color: inherit; text-decoration: none; }
  .status { color: #000; border: 1px solid #000; background: none; }
  section { break-inside: avoid; }
}
)css";

constexpr const char* kScript = R"js('use strict';
// The elements marked data-refresh="SECONDS" are fetched again from this
// page's own URL and replaced while the page is open (the overview's table, a
// job's progress). Without the script the pages are complete; they just do
// not update themselves. A section holding the keyboard focus waits, so that
// keyboard users do not lose their place.
(function () {
  function schedule(el) {
    var s = Number(el.getAttribute('data-refresh'));
    if (s > 0) setTimeout(function () { refresh(el); }, s * 1000);
  }
  function refresh(el) {
    if (el.contains(document.activeElement) && document.activeElement !== document.body) {
      schedule(el);
      return;
    }
    fetch(location.href, { credentials: 'same-origin', redirect: 'manual' })
      .then(function (r) {
        if (r.type === 'opaqueredirect' || r.status === 401) { location.reload(); return null; }
        if (!r.ok) throw new Error('HTTP ' + r.status);
        return r.text();
      })
      .then(function (text) {
        if (text === null) return;
        var fresh = new DOMParser().parseFromString(text, 'text/html').getElementById(el.id);
        if (!fresh) return;
        fresh = document.adoptNode(fresh);
        el.replaceWith(fresh);
        schedule(fresh);
      })
      .catch(function () { setTimeout(function () { refresh(el); }, 5000); });
  }
  document.querySelectorAll('[data-refresh][id]').forEach(schedule);
})();
// Times: the page says them in UTC (ISO 8601); the browser shows its own
// local time, with UTC in the title on hover.
(function () {
  function local(root) {
    root.querySelectorAll('time[datetime]').forEach(function (t) {
      var d = new Date(t.getAttribute('datetime'));
      if (isNaN(d.getTime())) return;
      var shown = d.toLocaleString(undefined, { dateStyle: 'medium', timeStyle: 'medium' });
      var utc = t.getAttribute('datetime');
      if (t.classList.contains('abs')) t.textContent = shown;
      t.title = shown + ' local time (' + utc + ' UTC)';
    });
  }
  local(document);
  new MutationObserver(function (ms) {
    ms.forEach(function (m) {
      m.addedNodes.forEach(function (n) { if (n.querySelectorAll) local(n); });
    });
  }).observe(document.body, { childList: true, subtree: true });
})();
// A banner while the service does not answer: the page then shows what the
// service knew when it last answered, and says since when.
(function () {
  var banner = document.getElementById('offline');
  if (!banner) return;
  var since = null;
  function check() {
    fetch('/console.css', { method: 'HEAD', cache: 'no-store', credentials: 'same-origin' })
      .then(function (r) {
        if (!r.ok) throw new Error('HTTP ' + r.status);
        since = null;
        banner.hidden = true;
      })
      .catch(function () {
        if (!since) since = new Date();
        banner.textContent = 'The lmcfg service is not answering (since ' +
          since.toLocaleTimeString() + '). This page shows what it knew then; it updates ' +
          'itself when the service answers again. Nothing you send now reaches the drives.';
        banner.setAttribute('role', 'alert');
        banner.hidden = false;
      })
      .then(function () { setTimeout(check, 5000); });
  }
  setTimeout(check, 5000);
})();
// A write button that needs a box ticked first (the restore without the
// values the drive cannot take) stays disabled until it is.
(function () {
  document.querySelectorAll('button[data-needs]').forEach(function (b) {
    var box = document.getElementById(b.getAttribute('data-needs'));
    if (!box) return;
    var sync = function () { b.disabled = !box.checked; };
    box.addEventListener('change', sync);
    sync();
  });
})();
)js";

}  // namespace

std::string_view Console::stylesheet() { return kStyle; }
std::string_view Console::script() { return kScript; }
std::string_view Console::content_security_policy() {
  return "default-src 'none'; style-src 'self'; script-src 'self'; img-src 'self'; "
         "connect-src 'self'; form-action 'self'; base-uri 'none'; frame-ancestors 'none'";
}

std::string_view Console::report_security_policy() {
  return "default-src 'none'; style-src 'unsafe-inline'; frame-ancestors 'none'";
}

}  // namespace lmcfg::serve
