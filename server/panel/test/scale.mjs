// The operator panel at a real scale, in headless Chromium: 100 scenes, the two waiting for the
// operator behind 98 nearer ones. What waits must come first, counted in the header and the
// page's title, each saying why; "unsafe" must show on its row, and an override of an unsafe
// module must stay marked; nothing may move under the pointer while scenes start waiting, end
// and appear, or while "Confirm activate" shows; a policy switch must take a confirmation; and
// a wrong token, a full credential, a lockout and a module's token must each be said as such,
// a module's token with no operator controls.
//
//   COOPERATION_SERVER=path/to/cooperation-server node test/scale.mjs

import {
  ACTIVATE, button, DEACTIVATE, Failure, launch, log, main, Module, OPTIONAL, pageUntil,
  requirements, REQUIRED, RESYNC_MS, row, RTC_WAITING, scene, startServer, status, STEP_MS, until,
} from './harness.mjs';

const TOTAL_MS = 60000;
const OPERATOR_TOKEN = 'scale-test-operator-0123456789abcdef';
const SECOND_TOKEN = 'scale-test-second-0123456789abcdefgh';
const MODULE_TOKEN = 'scale-test-module-0123456789abcdefghi';
const WRONG_TOKEN = 'scale-test-operator-0123456789abcdeX';
const PLACES = 2; // each credential's connections (--per-credential)
const CREDENTIALS = `operator panel ${OPERATOR_TOKEN}
operator second ${SECOND_TOKEN}
module planner ${MODULE_TOKEN} intersection crosswalk traffic_light lane_change_left
`;

// 97 scenes nearer than every other, none waiting; two far ones that wait (one because its
// module asks, one because the operator makes its module's policy required); one the module
// reports unsafe.
const hexOf = (n) => `5ca1e${String(n).padStart(3, '0')}5b7e4d219a0c1e2f3a4b5c6d`;
const NEAR = Array.from({ length: 97 }, (_, i) => scene(hexOf(i), 'intersection', { safe: true, state: RTC_WAITING, start: 5 + i }));
const ASKS = scene('a5c500005b7e4d219a0c1e2f3a4b5c6d', 'crosswalk', { safe: true, state: RTC_WAITING, start: 150, requested: true });
const REQUIRED_SCENE = scene('7e9d00005b7e4d219a0c1e2f3a4b5c6d', 'traffic_light', { safe: true, state: RTC_WAITING, start: 140 });
const UNSAFE = scene('05afe0005b7e4d219a0c1e2f3a4b5c6d', 'lane_change_left', { safe: false, state: RTC_WAITING, start: 4 });
const ALL = [...NEAR, ASKS, REQUIRED_SCENE, UNSAFE];
// Added while the pointer is over the scenes: the nearest of all.
const LATE = scene('1a7e00005b7e4d219a0c1e2f3a4b5c6d', 'intersection', { safe: true, state: RTC_WAITING, start: 1 });

const listed = (page) => page.evaluate(() => Array.from(document.querySelectorAll('#scene-rows tr'), (tr) => tr.dataset.uuid));

// Where every button on the page is, in the document's coordinates.
const places = (page) => page.evaluate(() => Array.from(document.querySelectorAll('#scene-rows button'), (b) => {
  const r = b.getBoundingClientRect();
  return `${b.closest('tr').dataset.uuid}/${b.dataset.decision}@${r.left + scrollX},${r.top + scrollY},${r.width}x${r.height}`;
}));

async function unmoved(page, before, what) {
  const after = await places(page);
  const moved = before.filter((place, i) => after[i] !== place);
  if (moved.length || after.length < before.length) {
    throw new Failure(`${what}: ${moved.length} buttons moved under the pointer (first: ${moved[0]} -> ${after[before.indexOf(moved[0])]})`);
  }
}

async function run(state) {
  const { binary, chromiumPath } = requirements();
  state.server = await startServer(binary, CREDENTIALS, ['--per-credential', String(PLACES)]);
  const { port } = state.server;
  const base = `http://127.0.0.1:${port}/`;
  log(`cooperation-server serving on 127.0.0.1:${port}, ${PLACES} connections a credential`);

  const module = new Module(port, MODULE_TOKEN);
  state.modules.push(module);
  await module.connect();
  for (const s of ALL) module.scenes.set(s.hex, s);
  for (const iface of new Set(ALL.map((s) => s.iface))) {
    await module.syncOnce(iface, ALL.filter((s) => s.iface === iface).map((s) => status(s)));
  }
  module.startCycle();
  // The operator, from Node: the traffic light's policy required, so its scene waits.
  const operator = new Module(port, SECOND_TOKEN);
  state.modules.push(operator);
  await operator.connect();
  await setPolicy(operator, 'traffic-signal', REQUIRED);
  log(`the module reports ${ALL.length} scenes; traffic-signal is made required`);

  state.browser = await launch(chromiumPath);
  const page = await state.browser.newPage({ viewport: { width: 1280, height: 800 } });
  const pageErrors = [];
  page.on('pageerror', (error) => pageErrors.push(error.message));
  await page.goto(`${base}#token=${OPERATOR_TOKEN}`, { timeout: STEP_MS });
  await pageUntil(page, 'the panel lists 100 scenes', () => document.querySelectorAll('#scene-rows tr').length === 100);

  // What waits comes first, nearest first among them, in view without scrolling; the header
  // and the title count it; each says why.
  await pageUntil(page, 'the two waiting scenes come first',
    (wanted) => JSON.stringify(Array.from(document.querySelectorAll('#scene-rows tr'), (tr) => tr.dataset.uuid).slice(0, 2)) === JSON.stringify(wanted),
    [REQUIRED_SCENE.hex, ASKS.hex]);
  await pageUntil(page, 'the header and the title count them',
    () => document.getElementById('waiting-count').textContent === '2 scenes wait for you'
      && document.title.startsWith('(2 waiting)'));
  const inView = await page.evaluate((selectors) => selectors.map((s) => document.querySelector(s).getBoundingClientRect().bottom <= innerHeight), [row(REQUIRED_SCENE), row(ASKS)]);
  if (!inView.every(Boolean)) throw new Failure(`a waiting scene is out of view on load: ${inView}`);
  const why = async (s) => (await page.locator(`${row(s)} [data-col="why"]`).textContent()).trim();
  if (!/^Waiting for you: policy required$/.test(await why(REQUIRED_SCENE))) throw new Failure(`the required scene says ${JSON.stringify(await why(REQUIRED_SCENE))}`);
  if (!/^Waiting for you: its module asks$/.test(await why(ASKS))) throw new Failure(`the asking scene says ${JSON.stringify(await why(ASKS))}`);
  if (!/unsafe/i.test(await why(UNSAFE))) throw new Failure(`the unsafe scene's row does not say unsafe: ${JSON.stringify(await why(UNSAFE))}`);
  if (await page.locator('#scene-rows tr[data-waiting="true"]').count() !== 2) throw new Failure('other scenes are marked waiting');
  log('the 2 waiting of 100 scenes come first, counted in the header and title, each saying why; the unsafe one says so');

  // Nothing moves under the pointer. The pointer rests on a button of the 10th row ...
  const target = button(NEAR[8], DEACTIVATE);
  await page.locator(target).scrollIntoViewIfNeeded();
  await page.hover(target);
  let before = await places(page);
  // ... a scene further down starts waiting: counted at once, but moved only later ...
  module.scenes.set(NEAR[60].hex, { ...NEAR[60], requested: true });
  await pageUntil(page, 'a scene that starts waiting is counted at once', () => document.getElementById('waiting-count').textContent === '3 scenes wait for you');
  await unmoved(page, before, 'a scene started waiting');
  // ... a scene above the pointer ends: its row stays, marked ended ...
  await module.remove(NEAR[2]);
  await pageUntil(page, 'the ended scene\'s row stays, marked', (selector) => document.querySelector(selector)?.dataset.ended === 'true', row(NEAR[2]));
  await unmoved(page, before, 'a scene above the pointer ended');
  // ... and a new, nearest scene is added at the end.
  await module.add(LATE);
  await pageUntil(page, 'the new scene is listed last while the pointer is over the scenes', (selector) => {
    const rows = document.querySelectorAll('#scene-rows tr');
    return rows[rows.length - 1] === document.querySelector(selector);
  }, row(LATE));
  await unmoved(page, before, 'a scene was added');
  log('while the pointer rests on the scenes, a scene starting to wait, ending or appearing moves no button');

  // The unsafe scene: a first click's confirmation lapses after 5 s, having sent nothing.
  await page.locator(button(UNSAFE, ACTIVATE)).scrollIntoViewIfNeeded();
  await page.click(button(UNSAFE, ACTIVATE), { timeout: STEP_MS });
  await pageUntil(page, 'the first click asks for a confirmation', (selector) => document.querySelector(selector).dataset.confirm === 'true', button(UNSAFE, ACTIVATE));
  await new Promise((resolve) => setTimeout(resolve, 5300));
  if (await page.locator(`${button(UNSAFE, ACTIVATE)}[data-confirm="false"]`).count() !== 1) throw new Failure('the confirmation did not lapse after 5 s');
  if (await page.locator(`${row(UNSAFE)} [data-col="cooperator"][data-decision="${ACTIVATE}"]`).count() !== 0) throw new Failure('an unconfirmed click activated the unsafe scene');
  log('an unconfirmed first click lapses after 5 s and sends nothing');
  // Its first click shows "Confirm activate", which moves no button.
  before = await places(page);
  await page.click(button(UNSAFE, ACTIVATE), { timeout: STEP_MS });
  await pageUntil(page, 'the first click asks for a confirmation', (selector) => document.querySelector(selector).dataset.confirm === 'true', button(UNSAFE, ACTIVATE));
  await unmoved(page, before, '"Confirm activate" appeared');
  await page.click(button(UNSAFE, ACTIVATE), { timeout: STEP_MS });
  await pageUntil(page, 'the override is marked on its row',
    (selector) => document.querySelector(selector).dataset.override === 'true'
      && /^Overridden by you: its module says unsafe$/.test(document.querySelector(`${selector} [data-col="why"]`).textContent),
    row(UNSAFE));
  await unmoved(page, before, 'the override was accepted');
  // It stays marked for as long as it stands: several publications later, still so.
  await new Promise((resolve) => setTimeout(resolve, 4 * RESYNC_MS));
  if (await page.locator(`${row(UNSAFE)}[data-override="true"]`).count() !== 1) throw new Failure('the override mark did not last');
  log('"Confirm activate" moves no button; the override of an unsafe module stays marked');

  // The pointer leaves: the order is made again, what waits first.
  await page.mouse.move(1, 1);
  await pageUntil(page, 'once the pointer leaves, the three waiting come first and the ended row is gone',
    ([waiting, ended]) => {
      const ids = Array.from(document.querySelectorAll('#scene-rows tr'), (tr) => tr.dataset.uuid);
      return JSON.stringify(ids.slice(0, 3).sort()) === JSON.stringify([...waiting].sort()) && !ids.includes(ended) && ids.length === 100;
    },
    [[REQUIRED_SCENE.hex, ASKS.hex, NEAR[60].hex], NEAR[2].hex]);
  const order = await listed(page);
  if (order[3] !== LATE.hex) throw new Failure(`the new nearest scene is not first after those waiting: ${order.slice(0, 5)}`);
  log('when the pointer leaves, the order is made again: waiting first, then nearest first');

  // A policy switch takes a confirmation; cancelled, nothing changes.
  const policyOf = async (behavior) => (await operator.call('/api/planning/cooperation/get_policies', 'autoware_adapi_v1_msgs/srv/GetCooperationPolicies', {}))
    .policies.find((p) => p.behavior === behavior && p.sequence === '').policy;
  await page.click('label[for="policy-crosswalk"]', { timeout: STEP_MS });
  await pageUntil(page, 'the crosswalk switch asks for a confirmation',
    () => document.getElementById('policy-dialog').open && /Make crosswalk required\?/.test(document.getElementById('policy-dialog-title').textContent));
  await page.click('#policy-dialog-cancel', { timeout: STEP_MS });
  await pageUntil(page, 'the dialog closes', () => !document.getElementById('policy-dialog').open);
  await new Promise((resolve) => setTimeout(resolve, 300));
  if (await policyOf('crosswalk') !== OPTIONAL) throw new Failure('a cancelled switch changed the policy');
  if (await page.locator('#policy-crosswalk').isChecked()) throw new Failure('a cancelled switch shows required');
  await page.click('label[for="policy-crosswalk"]', { timeout: STEP_MS });
  await page.click('#policy-dialog-confirm', { timeout: STEP_MS });
  await until('the confirmed switch makes crosswalk required', async () => (await policyOf('crosswalk')) === REQUIRED || 'not yet');
  log('a policy switch takes a confirmation; cancelled, it changes nothing');

  // Each way in that fails says why. A wrong token: said, forgotten, not retried; a right one
  // put in the address then connects.
  let other = await state.browser.newPage({ viewport: { width: 1280, height: 800 } });
  await other.goto(`${base}#token=${WRONG_TOKEN}`, { timeout: STEP_MS });
  await pageUntil(other, 'a wrong token is said as such',
    () => document.getElementById('connection').dataset.state === 'refused'
      && /not one of this node's credentials/.test(document.getElementById('connection').textContent));
  await other.evaluate((token) => { location.hash = `token=${token}`; }, OPERATOR_TOKEN);
  await pageUntil(other, 'the right token put in the address connects', () => document.getElementById('connection').dataset.state === 'connected');
  await other.close();
  // A full credential: said, and tried again until a place frees.
  const holder = new Module(port, SECOND_TOKEN);
  state.modules.push(holder);
  await holder.connect();
  other = await state.browser.newPage({ viewport: { width: 1280, height: 800 } });
  await other.goto(`${base}#token=${SECOND_TOKEN}`, { timeout: STEP_MS });
  await pageUntil(other, 'a full credential is said as such',
    (places) => /credential "second" has all (\d+) of its connections open/.exec(document.getElementById('connection').textContent)?.[1] === String(places),
    PLACES);
  holder.close();
  await pageUntil(other, 'once a place frees, the panel connects', () => document.getElementById('connection').dataset.state === 'connected');
  await other.close();
  // A module's token: said, and no operator control shown or enabled.
  other = await state.browser.newPage({ viewport: { width: 1280, height: 800 } });
  await other.goto(`${base}#token=${MODULE_TOKEN}`, { timeout: STEP_MS });
  await pageUntil(other, 'a module\'s token is said as such, read-only',
    () => document.getElementById('connection').dataset.state === 'connected'
      && /planning module "planner": read-only/.test(document.getElementById('connection').textContent)
      && document.querySelectorAll('#scene-rows tr').length > 0
      && document.querySelectorAll('#policies input').length > 0);
  const controls = await other.evaluate(() => ({
    buttons: Array.from(document.querySelectorAll('#scene-rows button')).filter((b) => b.offsetParent !== null).length,
    switches: Array.from(document.querySelectorAll('#policies input')).filter((i) => !i.disabled).length,
  }));
  if (controls.buttons || controls.switches) throw new Failure(`a module's token shows operator controls: ${JSON.stringify(controls)}`);
  await other.close();
  // A lockout: five wrong tokens from this address, then the right one waits it out.
  for (let i = 0; i < 5; i++) {
    await fetch(`${base}whoami`, { headers: { Authorization: `Bearer ${WRONG_TOKEN}` } });
  }
  other = await state.browser.newPage({ viewport: { width: 1280, height: 800 } });
  await other.goto(`${base}#token=${OPERATOR_TOKEN}`, { timeout: STEP_MS });
  await pageUntil(other, 'a lockout is said as such', () => /locked out/.test(document.getElementById('connection').textContent));
  await pageUntil(other, 'after the lockout, the panel connects', () => document.getElementById('connection').dataset.state === 'connected');
  await other.close();
  log('a wrong token, a full credential, a module\'s token and a lockout are each said; a module gets no controls');

  module.checkCycle();
  if (pageErrors.length) throw new Failure(`the page reported errors: ${pageErrors.join('; ')}`);
}

async function setPolicy(client, behavior, policy) {
  const response = await client.call('/api/planning/cooperation/set_policies', 'autoware_adapi_v1_msgs/srv/SetCooperationPolicies',
    { policies: [{ behavior, sequence: '', policy }] });
  if (!response.status.success) throw new Failure(`set_policies ${behavior}: ${JSON.stringify(response.status)}`);
}

main(TOTAL_MS, run);
