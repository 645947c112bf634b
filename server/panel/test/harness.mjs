// What the operator panel's browser tests share: the node on a free port with credentials, a
// planning module written with roslib in Node, Chromium, and the checks' helpers.

import { spawn } from 'node:child_process';
import { existsSync, mkdtempSync, rmSync, writeFileSync } from 'node:fs';
import net from 'node:net';
import os from 'node:os';
import path from 'node:path';
import { fileURLToPath } from 'node:url';

import { chromium } from 'playwright-core';
import ROSLIB from 'roslib';

const HERE = path.dirname(fileURLToPath(import.meta.url));
const SETTINGS = path.resolve(HERE, '../../../config/cooperation.param.yaml');
export const STEP_MS = 5000; // the longest any one step may wait
export const RESYNC_MS = 500; // a module's planning cycle, well inside the node's 10 s TTL

export const DEACTIVATE = 1;
export const ACTIVATE = 2;
export const AUTONOMOUS = 3;
export const UNDECIDED = 4;
export const OPTIONAL = 1;
export const REQUIRED = 2;
export const RTC_WAITING = 0;
export const RTC_RUNNING = 1;
export const RTC_ABORTING = 2;

const started = Date.now();
export const log = (text) => console.log(`[${((Date.now() - started) / 1000).toFixed(2)} s] ${text}`);

export class Failure extends Error {}

// --- The scenes a module reports --------------------------------------------------------------

export const bytes = (hex) => Array.from({ length: 16 }, (_, i) => parseInt(hex.slice(2 * i, 2 * i + 2), 16));

export function scene(hex, iface, { safe, state, start, finish = start, requested = false }) {
  return { hex, iface, uuid: bytes(hex), safe, state, start, finish, requested };
}

export const formatted = (hex) => `${hex.slice(0, 8)}-${hex.slice(8, 12)}-${hex.slice(12, 16)}-${hex.slice(16, 20)}-${hex.slice(20)}`;

export function status(s, state = s.state) {
  return {
    stamp: { sec: 0, nanosec: 0 },
    uuid: { uuid: s.uuid },
    module: { type: 0 },
    safe: s.safe,
    requested: s.requested,
    command_status: { type: 0 },
    state: { type: state },
    auto_mode: false,
    start_distance: s.start,
    finish_distance: s.finish,
  };
}

// --- Helpers ----------------------------------------------------------------------------------

export function within(ms, what, promise) {
  let timer;
  const timeout = new Promise((_, reject) => {
    timer = setTimeout(() => reject(new Failure(`${what}: no result within ${ms / 1000} s`)), ms);
  });
  return Promise.race([promise, timeout]).finally(() => clearTimeout(timer));
}

export async function until(what, check, ms = STEP_MS) {
  const deadline = Date.now() + ms;
  let last;
  for (;;) {
    last = await check();
    if (last === true) return;
    if (Date.now() > deadline) throw new Failure(`${what}: not so within ${ms / 1000} s${last ? ` (${last})` : ''}`);
    await new Promise((resolve) => setTimeout(resolve, 50));
  }
}

export function freePort() {
  return new Promise((resolve, reject) => {
    const probe = net.createServer();
    probe.once('error', reject);
    probe.listen(0, '127.0.0.1', () => {
      const { port } = probe.address();
      probe.close(() => resolve(port));
    });
  });
}

function accepts(port) {
  return new Promise((resolve) => {
    const socket = net.connect({ host: '127.0.0.1', port });
    socket.once('connect', () => { socket.destroy(); resolve(true); });
    socket.once('error', () => resolve(false));
  });
}

// --- The node ---------------------------------------------------------------------------------

// Starts the node on a free port with the credentials file `credentials` and `args` besides.
export async function startServer(binary, credentials, args = []) {
  for (let attempt = 1; ; attempt++) {
    const port = await freePort();
    const output = [];
    const folder = mkdtempSync(path.join(os.tmpdir(), 'credentials-'));
    const file = path.join(folder, 'credentials');
    writeFileSync(file, credentials, { mode: 0o600 });
    const child = spawn(binary, ['--listen', `127.0.0.1:${port}`, '--settings', SETTINGS, '--credentials', file, ...args], {
      stdio: ['ignore', 'pipe', 'pipe'],
      env: { ...process.env, NO_COLOR: '1', RUST_LOG: process.env.RUST_LOG || 'info' },
    });
    for (const stream of [child.stdout, child.stderr]) {
      stream.on('data', (chunk) => output.push(...chunk.toString().split('\n').filter(Boolean)));
    }
    let exited = null;
    // The credentials file goes with the node that read it.
    child.once('exit', (code, signal) => {
      exited = signal || `exit code ${code}`;
      rmSync(folder, { recursive: true, force: true });
    });
    child.once('error', (error) => { exited = error.message; });
    const server = { child, port, output, stopped: () => exited };
    try {
      await until(`cooperation-server accepting connections on port ${port}`, async () => {
        if (exited) throw new Failure(`cooperation-server stopped (${exited}):\n${output.join('\n')}`);
        return (await accepts(port)) || undefined;
      }, 10000);
      return server;
    } catch (error) {
      await stopServer(server);
      // Another process may have taken the port between the probe and the bind.
      if (attempt < 3 && output.some((line) => line.includes('cannot listen'))) continue;
      throw error;
    }
  }
}

export async function stopServer(server) {
  if (!server || server.stopped()) return;
  const gone = new Promise((resolve) => server.child.once('exit', resolve));
  server.child.kill('SIGINT');
  const timer = setTimeout(() => server.child.kill('SIGKILL'), 2000);
  await gone;
  clearTimeout(timer);
}


// --- The planning module ----------------------------------------------------------------------

// A planning module (or, with an operator's token, an operator's client) over roslib.
export class Module {
  constructor(port, token) {
    this.url = `ws://127.0.0.1:${port}/?token=${token}`;
    this.scenes = new Map(); // hex -> scene, re-synced every cycle
    this.responses = new Map(); // interface -> the last sync response
    this.errors = [];
  }

  async connect() {
    this.ros = new ROSLIB.Ros({ encoding: 'utf8' });
    const open = new Promise((resolve, reject) => {
      this.ros.once('connection', resolve);
      this.ros.once('error', (error) => reject(new Failure(`the module's connection: ${error.message || error}`)));
    });
    this.ros.connect(this.url);
    await within(STEP_MS, `the module connecting to ${this.url}`, open);
    this.sync = new ROSLIB.Service({ ros: this.ros, name: '/cooperation/rtc/sync', serviceType: 'cooperation_server/srv/SyncCooperateStatus' });
  }

  call(name, serviceType, args) {
    const service = new ROSLIB.Service({ ros: this.ros, name, serviceType });
    return within(STEP_MS, `the module calling ${name}`, new Promise((resolve, reject) => {
      service.callService(new ROSLIB.ServiceRequest(args), resolve, (error) => reject(new Failure(`${name}: ${error}`)));
    }));
  }

  async syncOnce(iface, statuses, removed = []) {
    const response = await this.call('/cooperation/rtc/sync', 'cooperation_server/srv/SyncCooperateStatus', { interface: iface, statuses, removed });
    if (!response.success) {
      throw new Failure(`sync of ${iface} refused: ${response.message || JSON.stringify(response.results)}`);
    }
    this.responses.set(iface, response);
    return response;
  }

  // Registers a scene; an aborting one runs first, as a module's would.
  async add(s) {
    if (s.state === RTC_ABORTING) await this.syncOnce(s.iface, [status(s, RTC_RUNNING)]);
    await this.syncOnce(s.iface, [status(s)]);
    this.scenes.set(s.hex, s);
  }

  // Stops reporting a scene, as a module that went silent: the node keeps it until it expires.
  silence(s) {
    this.scenes.delete(s.hex);
  }

  async remove(s) {
    this.scenes.delete(s.hex);
    await this.syncOnce(s.iface, [], [{ uuid: s.uuid }]);
  }

  // Re-reports every scene each cycle, as a planner does, so none expires.
  startCycle() {
    this.cycle = setInterval(() => {
      const byInterface = new Map();
      for (const s of this.scenes.values()) byInterface.set(s.iface, [...(byInterface.get(s.iface) || []), status(s)]);
      for (const [iface, statuses] of byInterface) {
        this.syncOnce(iface, statuses).catch((error) => this.errors.push(error.message));
      }
    }, RESYNC_MS);
  }

  checkCycle() {
    if (this.errors.length) throw new Failure(`the module's re-sync failed: ${this.errors[0]}`);
  }

  activation(s) {
    const response = this.responses.get(s.iface);
    return response && response.activations.find((a) => a.uuid.uuid.join() === s.uuid.join());
  }

  async policy(behavior) {
    const response = await this.call('/api/planning/cooperation/get_policies', 'autoware_adapi_v1_msgs/srv/GetCooperationPolicies', {});
    const found = response.policies.find((p) => p.behavior === behavior && p.sequence === '');
    if (!found) throw new Failure(`get_policies lists no ${behavior}: ${JSON.stringify(response.policies)}`);
    return found.policy;
  }

  close() {
    clearInterval(this.cycle);
    if (this.ros) this.ros.close();
  }
}


// --- The page ---------------------------------------------------------------------------------

export const row = (s) => `#scene-rows tr[data-uuid="${s.hex}"]`;
export const button = (s, decision) => `${row(s)} button[data-decision="${decision}"]`;

export async function pageUntil(page, what, fn, arg) {
  try {
    await page.waitForFunction(fn, arg, { timeout: STEP_MS, polling: 50 });
  } catch (error) {
    const message = await page.locator('#message').textContent().catch(() => '?');
    const connection = await page.locator('#connection').textContent().catch(() => '?');
    throw new Failure(`${what}: not so within ${STEP_MS / 1000} s `
      + `(connection: ${connection.trim()}; message: ${message.trim()}; ${error.message.split('\n')[0]})`);
  }
}

export const cellIs = (s, col, decision) => [
  ([selector, col, decision]) => {
    const cell = document.querySelector(`${selector} [data-col="${col}"]`);
    return cell && cell.dataset.decision === String(decision);
  },
  [row(s), col, decision],
];

// --- The run ----------------------------------------------------------------------------------

// The node's binary and Chromium, from the environment.
export function requirements() {
  const binary = process.env.COOPERATION_SERVER;
  if (!binary) throw new Failure('COOPERATION_SERVER is not set: give the path of the cooperation-server binary (cargo build --release -p cooperation-server)');
  if (!existsSync(binary)) throw new Failure(`COOPERATION_SERVER=${binary}: no such file`);
  const chromiumPath = process.env.CHROMIUM || '/usr/bin/chromium';
  if (!existsSync(chromiumPath)) throw new Failure(`no Chromium at ${chromiumPath}: set CHROMIUM`);
  return { binary, chromiumPath };
}

export function launch(chromiumPath) {
  return chromium.launch({
    executablePath: chromiumPath,
    headless: !process.env.HEADED,
    args: ['--no-sandbox', '--disable-gpu', '--disable-dev-shm-usage'],
  });
}

// Runs `run(state)` within `totalMs`, then closes what it left in `state` (`modules`,
// `browser`, `server`, and `close`, more to close), and exits 0 or 1 with what failed.
export async function main(totalMs, run) {
  const state = { modules: [], close: [] };
  const killServer = () => { if (state.server && !state.server.stopped()) state.server.child.kill('SIGKILL'); };
  process.once('exit', killServer);
  for (const signal of ['SIGINT', 'SIGTERM']) {
    process.once(signal, () => { killServer(); process.exit(130); });
  }
  const watchdog = setTimeout(() => {
    console.error(`FAIL: the run took longer than ${totalMs / 1000} s`);
    killServer();
    process.exit(1);
  }, totalMs);
  let failed = null;
  try {
    await run(state);
  } catch (error) {
    failed = error;
  }
  for (const module of state.modules) module.close();
  for (const close of state.close) close();
  if (state.browser) await state.browser.close().catch(() => {});
  await stopServer(state.server);
  clearTimeout(watchdog);
  if (failed) {
    console.error(`FAIL: ${failed instanceof Failure ? failed.message : failed.stack}`);
    if (state.server) console.error(`cooperation-server's last lines:\n${state.server.output.slice(-20).join('\n')}`);
    process.exit(1);
  }
  log('PASS');
  process.exit(0);
}
