// Helpers for the browser end-to-end tests: the runner every *.e2e.mjs
// goes through (runE2E), TAP-like check lines, child processes that are
// always ended, free ports, waiting on conditions.

import {spawn} from 'node:child_process';
import fs from 'node:fs';
import net from 'node:net';
import os from 'node:os';
import path from 'node:path';
import {fileURLToPath} from 'node:url';

// Where a test finds things: SEAMAP_SOURCE_DIR (the repository, default two
// folders up), SEAMAP_BIN (default build/seamap) and SEAMAP_ARTIFACTS (for
// screenshots; default a fresh temporary folder named after `tmpPrefix`).
export function testEnvironment(tmpPrefix = 'seamap-e2e-artifacts-') {
  const here = path.dirname(fileURLToPath(import.meta.url));
  const sourceDir = path.resolve(process.env.SEAMAP_SOURCE_DIR || path.join(here, '..', '..'));
  const seamap = process.env.SEAMAP_BIN || path.join(sourceDir, 'build', 'seamap');
  const artifacts = path.resolve(process.env.SEAMAP_ARTIFACTS || fs.mkdtempSync(path.join(os.tmpdir(), tmpPrefix)));
  const seeder = process.env.SEAMAP_SEED_DETECTIONS || path.join(path.dirname(seamap), 'seed_detections');
  return {sourceDir, seamap, artifacts, seeder};
}

export class Checks {
  constructor() {
    this.passed = 0;
    this.failed = 0;
    this.diagnose = null;   // async () => text: the page's state, printed under a failure
  }

  ok(name, detail = '') {
    this.passed++;
    console.log(`ok - ${name}${detail ? ` (${detail})` : ''}`);
  }

  fail(name, error) {
    this.failed++;
    const message = error instanceof Error ? error.message : String(error);
    console.log(`not ok - ${name}: ${message.split('\n')[0]}`);
  }

  // Runs one check; a failure is reported and the test goes on.
  async run(name, body) {
    try {
      const detail = await body();
      this.ok(name, detail);
      return true;
    } catch (error) {
      this.fail(name, error);
      if (this.diagnose) {
        const state = await this.diagnose().catch(e => `(no diagnosis: ${e.message})`);
        for (const line of String(state).split('\n')) console.log(`#   ${line}`);
      }
      return false;
    }
  }

  summary() {
    console.log(`${this.passed} passed, ${this.failed} failed`);
  }
}

const children = new Set();

export function startProcess(command, args, options = {}) {
  const child = spawn(command, args, {stdio: ['ignore', 'pipe', 'pipe'], ...options});
  children.add(child);
  child.output = '';
  const keep = chunk => {
    child.output += chunk;
    if (child.output.length > 200000) child.output = child.output.slice(-100000);
  };
  child.stdout.setEncoding('utf8').on('data', keep);
  child.stderr.setEncoding('utf8').on('data', keep);
  child.exited = new Promise(resolve => child.on('exit', (code, signal) => {
    children.delete(child);
    resolve({code, signal});
  }));
  return child;
}

export async function stopProcess(child, graceMs = 3000) {
  if (!child || child.exitCode !== null || child.signalCode !== null) return;
  child.kill('SIGTERM');
  const timer = setTimeout(() => child.kill('SIGKILL'), graceMs);
  await child.exited;
  clearTimeout(timer);
}

export function killAll() {
  for (const child of children) {
    try {
      child.kill('SIGKILL');
    } catch { /* already gone */ }
  }
}

export async function run(command, args, timeoutMs = 60000) {
  const child = startProcess(command, args);
  const timer = setTimeout(() => child.kill('SIGKILL'), timeoutMs);
  const {code, signal} = await child.exited;
  clearTimeout(timer);
  if (code !== 0) throw new Error(`${command} ${args.join(' ')} failed (${signal || code}): ${child.output.slice(-2000)}`);
  return child.output;
}

export function freePort() {
  return new Promise((resolve, reject) => {
    const server = net.createServer();
    server.unref();
    server.on('error', reject);
    server.listen(0, '127.0.0.1', () => {
      const {port} = server.address();
      server.close(() => resolve(port));
    });
  });
}

export const sleep = ms => new Promise(resolve => setTimeout(resolve, ms));

// Polls `probe` until it answers something truthy; throws `what` on timeout.
export async function waitFor(what, probe, {timeoutMs = 15000, intervalMs = 250} = {}) {
  const end = Date.now() + timeoutMs;
  let last;
  for (;;) {
    try {
      last = await probe();
      if (last) return last;
    } catch (error) {
      if (error.fatal) throw error;
      last = error;
    }
    if (Date.now() > end) {
      const why = last instanceof Error ? `: ${last.message}` : '';
      throw new Error(`timed out after ${timeoutMs / 1000} s waiting for ${what}${why}`);
    }
    await sleep(intervalMs);
  }
}

// Waits until the child prints a line matching `pattern`.
export function waitForOutput(child, pattern, timeoutMs) {
  return waitFor(`"${pattern}" from the server`, () => {
    if (child.exitCode !== null) {
      throw Object.assign(new Error(`server exited (${child.exitCode}): ${child.output.slice(-2000)}`), {fatal: true});
    }
    return pattern.test(child.output);
  }, {timeoutMs, intervalMs: 100});
}

// A TCP relay to 127.0.0.1:targetPort standing in for the ship's Wi-Fi: cut()
// drops every connection and refuses new ones until restore().
export async function linkProxy(targetPort) {
  const sockets = new Set();
  let up = true;
  const server = net.createServer(client => {
    if (!up) return client.destroy();
    const upstream = net.connect(targetPort, '127.0.0.1');
    for (const s of [client, upstream]) {
      sockets.add(s);
      s.on('close', () => sockets.delete(s));
      s.on('error', () => {});
    }
    client.pipe(upstream).pipe(client);
    client.on('close', () => upstream.destroy());
    upstream.on('close', () => client.destroy());
  });
  await new Promise(resolve => server.listen(0, '127.0.0.1', resolve));
  return {
    port: server.address().port,
    cut() {
      up = false;
      for (const s of sockets) s.destroy();
    },
    restore() { up = true; },
    close() {
      this.cut();
      server.close();
    },
  };
}

// Keeps, in the page, every interval started and not yet cleared with the
// stack that started it; window.__e2eIntervalsFrom(file) counts those
// started from a script whose URL contains `file`. Call before page.goto.
export function watchIntervals(page) {
  return page.addInitScript(() => {
    const running = new Map();
    const {setInterval: start, clearInterval: clear} = window;
    window.setInterval = (...args) => {
      const id = start(...args);
      running.set(id, new Error().stack || '');
      return id;
    };
    window.clearInterval = id => {
      running.delete(id);
      clear(id);
    };
    window.__e2eIntervalsFrom = file => [...running.values()].filter(stack => stack.includes(file)).length;
  });
}

// Debian's Chromium, headless, as every browser test runs it (SEAMAP_CHROMIUM: another binary).
export async function launchChromium() {
  const {chromium} = await import('playwright-core');
  return chromium.launch({
    executablePath: process.env.SEAMAP_CHROMIUM || '/usr/bin/chromium',
    args: ['--headless', '--no-sandbox', '--disable-gpu', '--disable-background-networking'],
  });
}

// Runs one end-to-end test: `body(t)` does the work and the checks, the
// runner everything around it, the same for every test:
//   - a watchdog: past `timeoutMs` (keep it under ctest's TIMEOUT, which
//     would kill this process and leave its children running) the children
//     are killed, the test fails and the process exits;
//   - t.work, a fresh folder (prefix `seamap-NAME-e2e-`), removed at the end;
//   - cleanup on success, failure, the watchdog and SIGINT/SIGTERM: browsers
//     from t.launchBrowser() closed, t.defer(fn) steps run (last first), the
//     children from t.start() stopped (last first), any other child killed;
//   - a body that throws fails the check `NAME end-to-end run`, with the end
//     of each t.start() child's output;
//   - the summary: 'N passed, N failed', where the screenshots are, and the
//     exit status (1 when a check failed).
// t also carries checks, artifacts (created), sourceDir, seamap, seeder and
// shot(page, name) (a screenshot into artifacts, its path answered).
export async function runE2E({name, timeoutMs, artifactsPrefix}, body) {
  const environment = testEnvironment(artifactsPrefix);
  fs.mkdirSync(environment.artifacts, {recursive: true});
  const work = fs.mkdtempSync(path.join(os.tmpdir(), `seamap-${name}-e2e-`));
  const checks = new Checks();
  const browsers = [];
  const deferred = [];
  const started = [];
  const removeWork = () => fs.rmSync(work, {recursive: true, force: true});
  // The watchdog and signals cannot wait for browsers to close: Playwright
  // kills the ones it launched when this process exits.
  const abandon = code => {
    killAll();
    removeWork();
    process.exit(code);
  };
  const giveUp = why => {
    checks.failed++;
    console.log(`not ok - ${why}`);
    checks.summary();
    abandon(1);
  };
  const watchdog = setTimeout(() => giveUp(`test finished within ${timeoutMs / 1000} s`), timeoutMs);
  const onSignal = signal => giveUp(`test ran to the end (stopped by ${signal})`);
  for (const signal of ['SIGINT', 'SIGTERM']) process.on(signal, onSignal);
  process.on('exit', killAll);

  const t = {
    ...environment, checks, work,
    start(command, args, options) {
      const child = startProcess(command, args, options);
      started.push(child);
      return child;
    },
    async launchBrowser() {
      const browser = await launchChromium();
      browsers.push(browser);
      return browser;
    },
    defer(step) {
      deferred.push(step);
    },
    async shot(page, shotName) {
      const file = path.join(environment.artifacts, `${shotName}.png`);
      await page.screenshot({path: file});
      return file;
    },
  };
  try {
    await body(t);
  } catch (error) {
    checks.fail(`${name} end-to-end run`, error);
    for (const child of started) {
      const what = `${path.basename(child.spawnfile)} ${child.spawnargs[1] ?? ''}`.trim();
      console.log(`# ${what} output:\n${child.output.slice(-3000).replace(/^/gm, '# ')}`);
    }
  } finally {
    for (const browser of browsers) await browser.close().catch(() => {});
    for (const step of deferred.reverse()) await Promise.resolve().then(step).catch(() => {});
    for (const child of started.reverse()) await stopProcess(child);
    killAll();
    removeWork();
    clearTimeout(watchdog);
  }
  checks.summary();
  console.log(`# screenshots in ${environment.artifacts}`);
  process.exit(checks.failed ? 1 : 0);
}
