// Headless Chromium over the DevTools protocol through --remote-debugging-pipe
// (file descriptors 3 and 4, NUL-separated JSON): no WebSocket, no npm
// package. Shared by check-report.js and walk-console.js.
'use strict';
const { spawn } = require('child_process');
const fs = require('fs');
const os = require('os');
const path = require('path');

function launch(chromium) {
  const profile = fs.mkdtempSync(path.join(os.tmpdir(), 'lmcfg-chromium-'));
  const chrome = spawn(chromium, [
    '--headless', '--disable-gpu', '--no-sandbox', '--remote-debugging-pipe',
    `--user-data-dir=${profile}`, '--no-first-run', '--no-default-browser-check',
    '--disable-extensions', '--disable-background-networking', '--disable-sync',
    '--disable-component-update', '--hide-scrollbars', '--mute-audio', 'about:blank',
  ], { stdio: ['ignore', 'ignore', 'pipe', 'pipe', 'pipe'] });
  const b = { stderr: '', listeners: [] };
  chrome.stderr.on('data', (d) => { b.stderr += d; });
  const toChrome = chrome.stdio[3];
  const fromChrome = chrome.stdio[4];
  let nextId = 1;
  const pending = new Map();
  let buffer = '';
  fromChrome.on('data', (chunk) => {
    buffer += chunk.toString('utf8');
    let end;
    while ((end = buffer.indexOf('\0')) >= 0) {
      const msg = JSON.parse(buffer.slice(0, end));
      buffer = buffer.slice(end + 1);
      if (msg.id && pending.has(msg.id)) {
        const { resolve, reject, method } = pending.get(msg.id);
        pending.delete(msg.id);
        if (msg.error) reject(new Error(`${method}: ${msg.error.message}`));
        else resolve(msg.result);
      } else if (msg.method) {
        for (const l of b.listeners) l(msg);
      }
    }
  });
  b.send = (method, params = {}, sessionId) => {
    const id = nextId++;
    const msg = { id, method, params };
    if (sessionId) msg.sessionId = sessionId;
    toChrome.write(JSON.stringify(msg) + '\0');
    return new Promise((resolve, reject) => pending.set(id, { resolve, reject, method }));
  };
  b.waitFor = (method, timeoutMs) => new Promise((resolve, reject) => {
    const t = setTimeout(() => reject(new Error(`timeout waiting for ${method}`)), timeoutMs);
    b.listeners.push((m) => { if (m.method === method) { clearTimeout(t); resolve(m.params); } });
  });
  b.cleanup = () => {
    try { chrome.kill('SIGKILL'); } catch (e) { /* gone */ }
    try { fs.rmSync(profile, { recursive: true, force: true }); } catch (e) { /* best effort */ }
  };
  return b;
}

// Collects into `out` what a page of the target `sessionId` should never do:
// console errors, exceptions and CSP violations (console_errors), requests
// other than ownUrl(url) allows (requests), alert() and friends (dialogs,
// answered so that the page goes on).
function watch(browser, sessionId, out, ownUrl) {
  browser.listeners.push((m) => {
    if (m.sessionId !== sessionId) return;
    const p = m.params;
    if (m.method === 'Network.requestWillBeSent' && !ownUrl(p.request.url)) out.requests.push(p.request.url);
    if (m.method === 'Runtime.consoleAPICalled' && (p.type === 'error' || p.type === 'assert'))
      out.console_errors.push(p.args.map((a) => a.value || a.description).join(' '));
    if (m.method === 'Runtime.exceptionThrown') out.console_errors.push(p.exceptionDetails.text);
    if (m.method === 'Log.entryAdded' && p.entry.level === 'error') out.console_errors.push(p.entry.text);
    if (m.method === 'Page.javascriptDialogOpening') {
      out.dialogs.push(p.message);
      browser.send('Page.handleJavaScriptDialog', { accept: true }, sessionId);
    }
  });
}

// Runs main() against `browser` with a time limit and prints its result as
// one JSON line on stdout; exit 1 on an error, 3 on the time limit.
function run(name, browser, main, timeoutMs) {
  const timer = setTimeout(() => {
    console.error(`${name}: timed out after ${timeoutMs / 1000} s\n` + browser.stderr);
    browser.cleanup();
    process.exit(3);
  }, timeoutMs);
  main().then((out) => {
    clearTimeout(timer);
    browser.cleanup();
    // Exit only once the whole answer is out (a pipe is written asynchronously).
    process.stdout.write(JSON.stringify(out) + '\n', () => process.exit(0));
  }, (e) => {
    clearTimeout(timer);
    console.error(`${name}: ` + e.message + '\n' + browser.stderr);
    browser.cleanup();
    process.exit(1);
  });
}

module.exports = { launch, run, watch };
