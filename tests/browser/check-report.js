#!/usr/bin/env node
// Loads an lmcfg HTML report in headless Chromium through the DevTools
// protocol (over --remote-debugging-pipe: no WebSocket, no npm package) and
// prints what the page holds as one JSON object on stdout, for
// tests/report/test_report.cpp to compare with the configuration:
//   load_ms (navigation start -> load event), render_ms (-> two animation
//   frames after load: laid out and painted), console_errors (console.error,
//   uncaught exceptions, browser log errors such as CSP violations), requests
//   (every URL the page asked for other than itself), dialogs (alert() ...),
//   params [[layer, upid]], curves [{id, diff, polylines: [{side, vertices,
//   setpoints, markers}]}], ct [ids], diff [[kind, key, layer]], scripts
//   (number of <script> elements), texts {needle: found in the text}, verdict.
// Usage: check-report.js --chromium PATH --html FILE --screenshot PNG
//        [--full-page] [--clip SELECTOR] [--text NEEDLE]...
'use strict';
const fs = require('fs');
const path = require('path');
const { launch, run, watch } = require('./cdp');

const args = { texts: [] };
for (let i = 2; i < process.argv.length; ++i) {
  const a = process.argv[i];
  if (a === '--full-page') args.fullPage = true;
  else if (a === '--text') args.texts.push(process.argv[++i]);
  else args[a.replace(/^--/, '')] = process.argv[++i];
}
if (!args.chromium || !args.html || !args.screenshot) {
  console.error('usage: check-report.js --chromium PATH --html FILE --screenshot PNG');
  process.exit(2);
}

const browser = launch(args.chromium);
const { send, waitFor } = browser;

// Runs in the page: the DOM facts the test compares.
function collect(needles) {
  const q = (sel, root = document) => Array.from(root.querySelectorAll(sel));
  // textContent, not innerText: content-visibility:auto leaves offscreen
  // sections out of innerText until they are rendered.
  const text = document.body.textContent;
  const texts = {};
  for (const n of needles) texts[n] = text.includes(n);
  return {
    title: document.title,
    params: q('tr.param').map((r) => [r.dataset.layer, r.dataset.upid]),
    curves: q('figure.curve').map((f) => ({
      id: Number(f.dataset.curveId),
      diff: f.classList.contains('diff'),
      polylines: q('polyline.setpoints', f).map((p) => ({
        side: p.dataset.side,
        vertices: p.points.numberOfItems,
        setpoints: Number(p.dataset.setpoints),
        markers: ['marker-start', 'marker-mid', 'marker-end'].every((m) => {
          const v = getComputedStyle(p).getPropertyValue(m);
          return v && v !== 'none' && document.getElementById(v.replace(/^url\("?#?|"?\)$/g, '')) !== null;
        }),
        width: p.getBoundingClientRect().width,
      })),
      delta: q('polyline.delta', f).length,
    })),
    ct: q('tr.ct').map((r) => Number(r.dataset.ctId)),
    diff: q('.diff').map((e) => [e.dataset.kind, e.dataset.key, e.dataset.layer || '']),
    verdict: (document.querySelector('.verdict') || {}).dataset ? Number((document.querySelector('.verdict') || { dataset: {} }).dataset.differences) : null,
    scripts: q('script').length,
    // Elements with an event handler attribute (an unescaped <svg onload=...>).
    handlers: q('*').filter((e) => Array.from(e.attributes).some((a) => a.name.startsWith('on'))).length,
    externalRefs: q('[src],[href]').map((e) => e.getAttribute('src') || e.getAttribute('href'))
      .filter((u) => !u.startsWith('#')),
    texts,
    height: document.documentElement.scrollHeight,
  };
}

async function main() {
  const url = 'file://' + path.resolve(args.html);
  const out = { console_errors: [], requests: [], dialogs: [] };
  const { targetId } = await send('Target.createTarget', { url: 'about:blank' });
  const { sessionId } = await send('Target.attachToTarget', { targetId, flatten: true });
  const s = (m, p) => send(m, p, sessionId);
  watch(browser, sessionId, out, (u) => u === url);
  await Promise.all(['Page.enable', 'Runtime.enable', 'Network.enable', 'Log.enable'].map((m) => s(m)));
  await s('Emulation.setDeviceMetricsOverride', { width: 1280, height: 900, deviceScaleFactor: 1, mobile: false });
  const loaded = waitFor('Page.loadEventFired', 60000);
  const t0 = Date.now();
  await s('Page.navigate', { url });
  await loaded;
  out.wall_load_ms = Date.now() - t0;
  const ev = async (expression) => {
    const r = await s('Runtime.evaluate', { expression, returnByValue: true, awaitPromise: true });
    if (r.exceptionDetails) throw new Error(`evaluate: ${r.exceptionDetails.text}`);
    return r.result.value;
  };
  out.render_ms = await ev('new Promise((r) => requestAnimationFrame(() => requestAnimationFrame(() => r(performance.now()))))');
  out.load_ms = await ev("performance.getEntriesByType('navigation')[0].loadEventEnd");
  out.dom_content_loaded_ms = await ev("performance.getEntriesByType('navigation')[0].domContentLoadedEventEnd");
  out.dom_interactive_ms = await ev("performance.getEntriesByType('navigation')[0].domInteractive");
  Object.assign(out, await ev(`(${collect.toString()})(${JSON.stringify(args.texts)})`));
  if (args.fullPage) {
    const height = Math.min(out.height, 16000);
    await s('Emulation.setDeviceMetricsOverride', { width: 1280, height, deviceScaleFactor: 1, mobile: false });
  }
  let clip;
  if (args.clip) {  // one element, at twice the resolution (for a close look)
    // Scrolled into view first: content-visibility:auto renders it only there.
    clip = await ev(`new Promise((done) => { const e = document.querySelector(${JSON.stringify(args.clip)});
      e.scrollIntoView(); requestAnimationFrame(() => requestAnimationFrame(() => { const r = e.getBoundingClientRect();
      done({ x: r.left + scrollX, y: r.top + scrollY, width: r.width, height: r.height, scale: 2 }); })); })`);
  }
  const shot = await s('Page.captureScreenshot', clip ? { format: 'png', clip } : { format: 'png' });
  fs.writeFileSync(args.screenshot, Buffer.from(shot.data, 'base64'));
  out.screenshot = args.screenshot;
  await send('Browser.close').catch(() => {});
  return out;
}

run('check-report.js', browser, main, 120000);
