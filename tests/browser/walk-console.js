#!/usr/bin/env node
// Walks lmcfg serve's web console in headless Chromium (DevTools protocol
// over a pipe, tests/browser/cdp.js) through a list of steps, as a person
// would: open a page, type into a field, press a button, wait for something
// to appear, press Tab, take a screenshot. Prints one JSON object on stdout:
//   steps: [{op, url, title, value}] (value: what "read", "eval", "tab" and
//   "wait" found), console_errors (console.error, exceptions, CSP
//   violations), requests (every URL outside the console's origin), dialogs.
// Usage: walk-console.js --chromium PATH --steps FILE.json
// A step is {"op": ...}:
//   viewport {width, height}      goto {url}          fill {selector, value}
//   submit {selector}: clicks it and waits for the page it loads
//   wait {selector, timeout_ms}   read: url, title, h1, the body's text
//   eval {expression}             tab {count}: the focused element afterwards
//   file {selector, path}: the file chosen in a file input
//   shot {file, full_page}
'use strict';
const fs = require('fs');
const { launch, run, watch } = require('./cdp');

const args = {};
for (let i = 2; i < process.argv.length; ++i) args[process.argv[i].replace(/^--/, '')] = process.argv[++i];
if (!args.chromium || !args.steps) {
  console.error('usage: walk-console.js --chromium PATH --steps FILE.json');
  process.exit(2);
}
const steps = JSON.parse(fs.readFileSync(args.steps, 'utf8'));
const browser = launch(args.chromium);
const { send, waitFor } = browser;

async function main() {
  const out = { steps: [], console_errors: [], requests: [], dialogs: [] };
  const { targetId } = await send('Target.createTarget', { url: 'about:blank' });
  const { sessionId } = await send('Target.attachToTarget', { targetId, flatten: true });
  const s = (m, p) => send(m, p, sessionId);
  let origin = null;
  watch(browser, sessionId, out, (u) => !origin || u.startsWith(origin));
  await Promise.all(['Page.enable', 'Runtime.enable', 'Network.enable', 'Log.enable'].map((m) => s(m)));
  let viewport = { width: 1280, height: 900 };
  await s('Emulation.setDeviceMetricsOverride', { ...viewport, deviceScaleFactor: 1, mobile: false });
  const ev = async (expression) => {
    const r = await s('Runtime.evaluate', { expression, returnByValue: true, awaitPromise: true });
    if (r.exceptionDetails) throw new Error(`evaluate ${expression}: ${r.exceptionDetails.text}`);
    return r.result.value;
  };
  const q = (sel) => JSON.stringify(sel);
  for (const step of steps) {
    let value = null;
    switch (step.op) {
      case 'viewport':
        viewport = { width: step.width, height: step.height };
        await s('Emulation.setDeviceMetricsOverride', { ...viewport, deviceScaleFactor: 1, mobile: false });
        break;
      case 'goto': {
        origin = origin || new URL(step.url).origin;
        const loaded = waitFor('Page.loadEventFired', 30000);
        await s('Page.navigate', { url: step.url });
        await loaded;
        break;
      }
      case 'fill':
        await ev(`(() => { const e = document.querySelector(${q(step.selector)});
          if (!e) throw new Error('no element ' + ${q(step.selector)}); e.value = ${q(step.value)}; })()`);
        break;
      case 'submit': {
        const loaded = waitFor('Page.loadEventFired', 30000);
        await ev(`(() => { const e = document.querySelector(${q(step.selector)});
          if (!e) throw new Error('no element ' + ${q(step.selector)}); e.click(); })()`);
        await loaded;
        break;
      }
      case 'wait': {
        const until = Date.now() + (step.timeout_ms || 20000);
        for (;;) {
          if (await ev(`document.querySelector(${q(step.selector)}) !== null`)) { value = true; break; }
          if (Date.now() > until) { value = false; break; }
          await new Promise((r) => setTimeout(r, 200));
        }
        break;
      }
      case 'read':
        value = await ev(`({ h1: (document.querySelector('h1') || {}).textContent || '',
          text: document.body.textContent, scripts: document.querySelectorAll('script:not([src])').length,
          handlers: Array.from(document.querySelectorAll('*')).filter((e) =>
            Array.from(e.attributes).some((a) => a.name.startsWith('on'))).length,
          width: document.documentElement.scrollWidth })`);
        break;
      case 'eval':
        value = await ev(step.expression);
        break;
      case 'file': {
        // A file chosen in a file input, as the file dialog would choose it.
        const { root } = await s('DOM.getDocument', { depth: 0 });
        const { nodeId } = await s('DOM.querySelector', { nodeId: root.nodeId, selector: step.selector });
        if (!nodeId) throw new Error(`no element ${step.selector}`);
        await s('DOM.setFileInputFiles', { nodeId, files: [step.path] });
        value = step.path;
        break;
      }
      case 'tab':
        for (let i = 0; i < (step.count || 1); ++i) {
          await s('Input.dispatchKeyEvent', { type: 'keyDown', key: 'Tab', code: 'Tab', windowsVirtualKeyCode: 9 });
          await s('Input.dispatchKeyEvent', { type: 'keyUp', key: 'Tab', code: 'Tab', windowsVirtualKeyCode: 9 });
        }
        value = await ev(`(() => { const e = document.activeElement; const st = getComputedStyle(e);
          return { tag: e.tagName, text: (e.textContent || e.value || '').trim().slice(0, 80),
                   outline: st.outlineStyle, outline_width: parseFloat(st.outlineWidth) || 0 }; })()`);
        break;
      case 'shot': {
        let metrics = null;
        if (step.full_page) {
          const height = Math.min(await ev('document.documentElement.scrollHeight'), 8000);
          metrics = { width: viewport.width, height };
          await s('Emulation.setDeviceMetricsOverride', { ...metrics, deviceScaleFactor: 1, mobile: false });
        }
        const shot = await s('Page.captureScreenshot', { format: 'png' });
        fs.writeFileSync(step.file, Buffer.from(shot.data, 'base64'));
        if (metrics)
          await s('Emulation.setDeviceMetricsOverride', { ...viewport, deviceScaleFactor: 1, mobile: false });
        value = step.file;
        break;
      }
      default:
        throw new Error(`unknown step ${JSON.stringify(step)}`);
    }
    const url = await ev('location.href');
    const title = await ev('document.title');
    out.steps.push({ op: step.op, url, title, value });
  }
  await send('Browser.close').catch(() => {});
  return out;
}

run('walk-console.js', browser, main, 240000);
