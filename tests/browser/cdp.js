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

module.exports = { launch };
