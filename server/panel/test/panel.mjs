// The operator panel in headless Chromium against a running cooperation-server.
//
//   COOPERATION_SERVER=path/to/cooperation-server npm test
//
// A planning module (roslib in Node) registers scenes through /cooperation/rtc/sync and keeps
// them alive; the panel must show them waiting first, then nearest first, send an operator
// decision the module then sees, switch a policy the node then reports, and show a refusal of
// the node. The screenshot goes to $SCREENSHOT, or to target/panel-test/. Environment:
// CHROMIUM (default /usr/bin/chromium), HEADED=1 to watch. `scale.mjs` tests the panel at 100
// scenes and the messages of each way in.

import { mkdirSync, mkdtempSync, rmSync, writeFileSync } from 'node:fs';
import http from 'node:http';
import os from 'node:os';
import path from 'node:path';
import { fileURLToPath } from 'node:url';

import {
  ACTIVATE, button, cellIs, DEACTIVATE, Failure, formatted, launch, log, main, Module, OPTIONAL,
  pageUntil, requirements, REQUIRED, RESYNC_MS, row, RTC_ABORTING, RTC_RUNNING, RTC_WAITING, scene,
  startServer, STEP_MS, stopServer, until,
} from './harness.mjs';

const TOTAL_MS = 50000; // the whole run

// The node runs with credentials: the panel gets the operator's token in its address, the
// module presents its own, bound to the interfaces it reports for.
const OPERATOR_TOKEN = 'panel-test-operator-0123456789abcdef';
const MODULE_TOKEN = 'panel-test-module-0123456789abcdefgh';
const CREDENTIALS = `operator panel ${OPERATOR_TOKEN}
module planner ${MODULE_TOKEN} lane_change_left intersection crosswalk traffic_light
`;

// --- The scenes the module reports ------------------------------------------------------------

// The module judges the lane change unsafe (module decision deactivate); the crosswalk asks
// for an operator decision (requested), so the vehicle waits for one; the crossing is
// aborting, so the node accepts no command for it.
const LANE_CHANGE = scene('a17e0c525b7e4d219a0c1e2f3a4b5c6d', 'lane_change_left', { safe: false, state: RTC_WAITING, start: 30, finish: 80 });
const INTERSECTION = scene('3f2a9c105b7e4d219a0c1e2f3a4b5c6d', 'intersection', { safe: true, state: RTC_WAITING, start: 12 });
const CROSSWALK = scene('c0ffee005b7e4d219a0c1e2f3a4b5c6d', 'crosswalk', { safe: true, state: RTC_RUNNING, start: 45, requested: true });
const TRAFFIC_LIGHT = scene('7a1c3e905b7e4d219a0c1e2f3a4b5c6d', 'traffic_light', { safe: true, state: RTC_ABORTING, start: 60 });
// Reported last, asking for an operator decision: the screenshot shows it waiting.
const ASKING = scene('5eed00015b7e4d219a0c1e2f3a4b5c6d', 'intersection', { safe: true, state: RTC_WAITING, start: 20, requested: true });
const NEAREST_FIRST = [INTERSECTION, LANE_CHANGE, CROSSWALK, TRAFFIC_LIGHT];
// The crosswalk waits for the operator: it comes first, the others after it nearest first.
const LISTED = [CROSSWALK, INTERSECTION, LANE_CHANGE, TRAFFIC_LIGHT];

// --- The run ----------------------------------------------------------------------------------

async function run(state) {
  const { binary, chromiumPath } = requirements();
  state.server = await startServer(binary, CREDENTIALS);
  const { port } = state.server;
  log(`cooperation-server serving on 127.0.0.1:${port}`);

  const module = new Module(port, MODULE_TOKEN);
  state.modules.push(module);
  await module.connect();
  for (const s of NEAREST_FIRST) await module.add(s);
  module.startCycle();
  log(`the module reports ${NEAREST_FIRST.length} scenes and re-syncs every ${RESYNC_MS} ms`);

  state.browser = await launch(chromiumPath);
  const page = await state.browser.newPage({ viewport: { width: 1280, height: 800 } });
  const pageErrors = [];
  page.on('pageerror', (error) => pageErrors.push(error.message));
  page.on('console', (message) => { if (message.type() === 'error') pageErrors.push(message.text()); });
  // The page's rosbridge connection passes through here, so a step can hold back the node's
  // publications and make the page's view stale, as a slow link would.
  let frozen = false;
  await page.routeWebSocket(/.*/, (ws) => {
    const server = ws.connectToServer();
    ws.onMessage((message) => server.send(message));
    server.onMessage((message) => {
      if (frozen && String(message).startsWith('{"op":"publish"')) return;
      ws.send(message);
    });
  });

  // Without the operator's token the panel does not connect, and says what it needs.
  const tokenless = await state.browser.newPage();
  await tokenless.goto(`http://127.0.0.1:${port}/`, { timeout: STEP_MS });
  await pageUntil(tokenless, 'a panel without a token says it needs one', () => {
    const indicator = document.getElementById('connection');
    return indicator.dataset.state === 'refused' && indicator.textContent.includes('#token=');
  });
  await tokenless.close();
  log('a panel without a token is not let in, and says it needs one');

  await page.goto(`http://127.0.0.1:${port}/#token=${OPERATOR_TOKEN}`, { timeout: STEP_MS });
  await pageUntil(page, 'the connection indicator says connected',
    () => document.getElementById('connection').dataset.state === 'connected');
  log('the page is connected');
  // The token is taken out of the address as soon as it is read, and a reload still connects.
  const address = page.url();
  if (address.includes('token=') || address.includes(OPERATOR_TOKEN)) {
    throw new Failure(`the token is still in the address: ${address}`);
  }
  await page.reload({ timeout: STEP_MS });
  await pageUntil(page, 'after a reload, the connection indicator says connected',
    () => document.getElementById('connection').dataset.state === 'connected');
  log('the token leaves the address once read, and a reload of the tab still connects');

  // A page of another origin cannot connect (cross-site WebSocket hijacking), while the same
  // script on the panel's own page can: a page served from another port of this host, and a
  // file:// page (origin null). Both are real local pages: a page Playwright fulfils itself
  // has no address, and Chromium's local-network checks would refuse it whatever the node did.
  const tryConnect = (url) => new Promise((resolve) => {
    const socket = new WebSocket(url);
    socket.onopen = () => { resolve('open'); socket.close(); };
    socket.onerror = () => resolve('refused');
    setTimeout(() => resolve('no answer'), 4000);
  });
  // Even with the operator's token, a page of another origin is refused.
  const nodeUrl = `ws://127.0.0.1:${port}/?token=${OPERATOR_TOKEN}`;
  const own = await page.evaluate(tryConnect, nodeUrl);
  if (own !== 'open') throw new Failure(`the panel's own page could not open a second WebSocket: ${own}`);
  state.strangerHits = 0;
  state.strangerServer = http.createServer((request, response) => {
    if (request.url === '/exfiltrate') state.strangerHits += 1;
    response.writeHead(200, { 'content-type': 'text/html' });
    response.end('<title>another origin</title>');
  });
  await new Promise((resolve) => state.strangerServer.listen(0, '127.0.0.1', resolve));
  state.close.push(() => state.strangerServer.close());
  const strangerDir = mkdtempSync(path.join(os.tmpdir(), 'stranger-'));
  state.close.push(() => rmSync(strangerDir, { recursive: true, force: true }));
  writeFileSync(path.join(strangerDir, 'stranger.html'), '<title>a file</title>');
  const stranger = await state.browser.newPage();
  for (const url of [`http://127.0.0.1:${state.strangerServer.address().port}/`, `file://${strangerDir}/stranger.html`]) {
    await stranger.goto(url, { timeout: STEP_MS });
    const answer = await stranger.evaluate(tryConnect, nodeUrl);
    if (answer !== 'refused') throw new Failure(`a page at ${url} opened a WebSocket to the node: ${answer}`);
  }
  await stranger.close();
  log('pages of other origins are refused; the panel\'s own page is not');

  // The panel's own page may not call out: a script injected into it could not reach another
  // server (its Content-Security-Policy allows connections to the node only).
  const errorsBefore = pageErrors.length;
  await page.evaluate(async (url) => {
    try { await fetch(url, { mode: 'no-cors' }); } catch { /* refused */ }
  }, `http://127.0.0.1:${state.strangerServer.address().port}/exfiltrate`);
  await new Promise((resolve) => setTimeout(resolve, 200));
  if (state.strangerHits !== 0) throw new Failure('the panel\'s page sent a request to another server');
  const violations = pageErrors.splice(errorsBefore);
  if (!violations.every((text) => /Content Security Policy/.test(text))) {
    throw new Failure(`unexpected page errors: ${violations.join('; ')}`);
  }
  log('the panel\'s page cannot connect to another server');

  // The scenes appear, the one waiting for the operator first, then nearest first, velocity
  // and steering factors merged.
  const wanted = LISTED.map((s) => s.hex);
  await pageUntil(page, `the table lists the scenes waiting first, then nearest first (${wanted.join(', ')})`,
    (wanted) => JSON.stringify(Array.from(document.querySelectorAll('#scene-rows tr'), (tr) => tr.dataset.uuid)) === JSON.stringify(wanted),
    wanted);
  const distance = (await page.locator(`${row(LANE_CHANGE)} [data-col="distance"]`).textContent()).trim();
  if (distance !== '30.0 m\n→ 80.0 m') throw new Failure(`the lane change's distance reads ${JSON.stringify(distance)}`);
  if (!(await page.locator(button(TRAFFIC_LIGHT, ACTIVATE)).isDisabled())) {
    throw new Failure('the aborting scene\'s buttons are enabled, though the node accepts no command for it');
  }
  await pageUntil(page, 'the lane change shows module decision deactivate', ...cellIs(LANE_CHANGE, 'autonomous', DEACTIVATE));
  log('the scenes are listed waiting first, then nearest first');

  // Each row names its scene in full, shows the merged decision the vehicle drives with, and
  // marks the scene the vehicle waits on the operator for.
  for (const s of NEAREST_FIRST) {
    const id = (await page.locator(`${row(s)} [data-col="uuid"]`).textContent()).trim();
    if (id !== formatted(s.hex)) throw new Failure(`scene ${s.hex} is shown as ${JSON.stringify(id)}, not in full`);
  }
  await pageUntil(page, 'the intersection (safe, optional) shows merged activate', ...cellIs(INTERSECTION, 'merged', ACTIVATE));
  await pageUntil(page, 'the lane change (unsafe) shows merged deactivate', ...cellIs(LANE_CHANGE, 'merged', DEACTIVATE));
  await pageUntil(page, 'the crosswalk (requested) shows merged deactivate', ...cellIs(CROSSWALK, 'merged', DEACTIVATE));
  await pageUntil(page, 'the crosswalk, which asks, is marked as waiting for the operator, and only it',
    ([waiting, others]) => document.querySelector(waiting).dataset.waiting === 'true'
      && /Waiting for you/.test(document.querySelector(waiting).textContent)
      && others.every((selector) => document.querySelector(selector).dataset.waiting === 'false'),
    [row(CROSSWALK), [row(INTERSECTION), row(LANE_CHANGE), row(TRAFFIC_LIGHT)]]);
  log('full identifiers, merged decisions, and the scene waiting for the operator are shown');

  // Activating a scene its module reports unsafe takes a second, confirming click.
  await page.click(button(LANE_CHANGE, ACTIVATE), { timeout: STEP_MS });
  await pageUntil(page, 'the first click on activate asks for confirmation',
    (selector) => document.querySelector(selector).dataset.confirm === 'true'
      && document.getElementById('message').dataset.kind === 'warning', button(LANE_CHANGE, ACTIVATE));
  await new Promise((resolve) => setTimeout(resolve, 2 * RESYNC_MS));
  const unconfirmed = module.activation(LANE_CHANGE);
  if (!unconfirmed || unconfirmed.force_activated) throw new Failure(`one click activated an unsafe scene: ${JSON.stringify(unconfirmed)}`);
  log('one click on activate for an unsafe scene sends nothing and asks to confirm');

  // Activate: the operator decision column changes, and the module is told.
  await page.click(button(LANE_CHANGE, ACTIVATE), { timeout: STEP_MS });
  await pageUntil(page, 'the lane change shows operator decision activate', ...cellIs(LANE_CHANGE, 'cooperator', ACTIVATE));
  await pageUntil(page, 'the lane change shows merged activate', ...cellIs(LANE_CHANGE, 'merged', ACTIVATE));
  await pageUntil(page, 'the activate button shows pressed',
    (selector) => document.querySelector(selector).getAttribute('aria-pressed') === 'true', button(LANE_CHANGE, ACTIVATE));
  await until('the module\'s sync says the lane change is force-activated', () => {
    module.checkCycle();
    const a = module.activation(LANE_CHANGE);
    return (a && a.activated && a.force_activated) || JSON.stringify(a);
  });
  log('activate is shown, and the module sees the scene force-activated');

  // A policy switch: lane change from optional to required.
  const before = await module.policy('lane-change');
  if (before !== OPTIONAL) throw new Failure(`lane-change's policy is ${before} before the switch, not optional (${OPTIONAL})`);
  await page.click('label[for="policy-lane-change"]', { timeout: STEP_MS });
  await pageUntil(page, 'the switch asks for a confirmation first', () => document.getElementById('policy-dialog').open);
  await page.click('#policy-dialog-confirm', { timeout: STEP_MS });
  await pageUntil(page, 'the lane-change switch shows required (read back from get_policies)', () => {
    const input = document.getElementById('policy-lane-change');
    return input.checked && !input.disabled && input.closest('li').dataset.value === 'required';
  });
  const after = await module.policy('lane-change');
  if (after !== REQUIRED) throw new Failure(`get_policies says lane-change is ${after} after the switch, not required (${REQUIRED})`);
  log('the lane-change policy switched to required');

  // A refusal: the page still shows a scene the module has just removed.
  frozen = true;
  await module.remove(INTERSECTION);
  await page.click(button(INTERSECTION, ACTIVATE), { timeout: STEP_MS });
  await pageUntil(page, 'the message area shows the node\'s refusal of a command for a removed scene', () => {
    const message = document.getElementById('message');
    return message.dataset.kind === 'error' && /refused: .*retired scene/.test(message.textContent);
  });
  const refusal = (await page.locator('#message').textContent()).trim();
  log(`the refusal is shown: ${refusal}`);
  frozen = false;
  // The pointer is still over the scenes: the removed scene's row stays in its place, ended,
  // until the pointer leaves them.
  await pageUntil(page, 'under the pointer, the removed scene\'s row stays, marked ended',
    (selector) => document.querySelector(selector)?.dataset.ended === 'true', row(INTERSECTION));
  await page.mouse.move(1, 1);
  await pageUntil(page, 'the removed scene leaves the table', (selector) => !document.querySelector(selector), row(INTERSECTION));

  // The next success replaces the refusal.
  await page.click(button(CROSSWALK, DEACTIVATE), { timeout: STEP_MS });
  await pageUntil(page, 'the crosswalk shows operator decision deactivate', ...cellIs(CROSSWALK, 'cooperator', DEACTIVATE));
  await pageUntil(page, 'the message area shows the acceptance instead of the refusal', () => {
    const message = document.getElementById('message');
    return message.dataset.kind === 'ok' && !message.textContent.includes('refused');
  });
  log('a success replaced the refusal');

  // The crosswalk decided, it no longer waits for the operator.
  await pageUntil(page, 'the decided crosswalk is no longer marked as waiting',
    (selector) => document.querySelector(selector).dataset.waiting === 'false', row(CROSSWALK));

  // A module that stops reporting a scene: its row's age grows and it is marked stale.
  module.silence(TRAFFIC_LIGHT);
  await pageUntil(page, 'the scene its module stopped reporting is marked stale, the others are not',
    ([silent, others]) => document.querySelector(silent).dataset.stale === 'true'
      && /^\d+\.\d s$/.test(document.querySelector(`${silent} [data-col="age"]`).textContent)
      && others.every((selector) => document.querySelector(selector).dataset.stale === 'false'),
    [row(TRAFFIC_LIGHT), [row(LANE_CHANGE), row(CROSSWALK)]]);
  log('a silent module\'s scene is marked stale');

  // Every message is kept, newest first.
  const history = await page.locator('#history li').allTextContents();
  for (const wanted of ['reports it unsafe', 'activate accepted', 'refused', 'deactivate accepted']) {
    if (!history.some((line) => line.includes(wanted))) throw new Failure(`the history has no "${wanted}": ${JSON.stringify(history)}`);
  }
  if (!history[0].includes('deactivate accepted')) throw new Failure(`the newest message is not first: ${JSON.stringify(history)}`);
  log(`the history keeps every message (${history.length})`);

  // At 800 px wide, the scenes fit: nothing scrolls sideways, every button is in view.
  const narrow = await state.browser.newPage({ viewport: { width: 800, height: 1000 } });
  await narrow.goto(`http://127.0.0.1:${port}/#token=${OPERATOR_TOKEN}`, { timeout: STEP_MS });
  await pageUntil(narrow, 'the narrow page lists the scenes',
    () => document.querySelectorAll('#scene-rows tr').length >= 3);
  const overflow = await narrow.evaluate(() => {
    const width = document.documentElement.clientWidth;
    const wide = document.documentElement.scrollWidth > width;
    const outside = Array.from(document.querySelectorAll('#scene-rows button'))
      .filter((b) => b.getBoundingClientRect().right > width || b.getBoundingClientRect().left < 0).length;
    return { wide, outside, width, scroll: document.documentElement.scrollWidth };
  });
  if (overflow.wide || overflow.outside) throw new Failure(`at 800 px the page overflows: ${JSON.stringify(overflow)}`);
  await narrow.close();
  log('at 800 px wide the scenes fit the window');

  // A new scene that asks for the operator, for the screenshot.
  await module.add(ASKING);
  await pageUntil(page, 'a new scene that asks is marked as waiting',
    (selector) => document.querySelector(selector)?.dataset.waiting === 'true', row(ASKING));

  module.checkCycle();
  if (pageErrors.length) throw new Failure(`the page reported errors: ${pageErrors.join('; ')}`);

  const file = process.env.SCREENSHOT || path.resolve(
    path.dirname(fileURLToPath(import.meta.url)), '../../../target/panel-test/operator-panel.png');
  mkdirSync(path.dirname(path.resolve(file)), { recursive: true });
  await page.mouse.move(1, 1);
  await page.evaluate(() => scrollTo(0, 0));
  await page.screenshot({ path: file, timeout: STEP_MS });
  log(`screenshot: ${file}`);

  // The node goes away: the last acceptance does not stay on show as if it still held.
  await stopServer(state.server);
  await pageUntil(page, 'the message area says the connection was lost',
    () => document.getElementById('message').dataset.kind === 'error'
      && /lost/.test(document.getElementById('message').textContent));
  log('a lost connection replaces the last answer with a warning');
}

main(TOTAL_MS, run);
