// The operator panel on the stack mode's node, in headless Chromium: run by tools/stack-test's
// peer while its planners, which speak upstream's RTC endpoints, report a scene their module
// says is unsafe. The panel shows the scene with no operator decision (none, not deactivate),
// the operator's confirmed activate is answered once the module took it, and the decisions no
// upstream interface can take for one scene (autonomous, none) are not offered. Whether the
// module itself took the activate is the peer's to check.
//
//   CHROMIUM=/usr/bin/chromium node test/stack.mjs http://127.0.0.1:9090/ <scene's 32 hex digits>
//
// Prints one line per step; exits 0, or 1 with what failed.

import { existsSync } from 'node:fs';

import {
  ACTIVATE, AUTONOMOUS, DEACTIVATE, Failure, STEP_MS, UNDECIDED, button, cellIs, launch, log, pageUntil, row,
} from './harness.mjs';

const [url, hex] = process.argv.slice(2);
if (!url || !/^[0-9a-f]{32}$/.test(hex || '')) {
  console.error('usage: node test/stack.mjs URL SCENE_HEX');
  process.exit(2);
}
const scene = { hex };

async function run(state) {
  const chromiumPath = process.env.CHROMIUM || '/usr/bin/chromium';
  if (!existsSync(chromiumPath)) throw new Failure(`no Chromium at ${chromiumPath}: set CHROMIUM`);
  state.browser = await launch(chromiumPath);
  const page = await state.browser.newPage();
  await page.goto(url, { timeout: STEP_MS });
  await pageUntil(page, 'the scene is shown', (selector) => document.querySelector(selector) !== null, row(scene));
  await pageUntil(page, 'module decision deactivate, operator decision none (not deactivate)',
    ([selector, undecided, deactivate]) => {
      const cell = (col) => document.querySelector(`${selector} [data-col="${col}"]`);
      return cell('cooperator')?.dataset.decision === String(undecided)
        && cell('autonomous')?.dataset.decision === String(deactivate);
    }, [row(scene), UNDECIDED, DEACTIVATE]);
  const module = await page.locator(`${row(scene)} [data-col="module"]`).textContent();
  log(`the panel shows the planner's scene: ${module.trim()}, module decision deactivate, operator decision none`);

  await page.click(button(scene, ACTIVATE), { timeout: STEP_MS });
  await pageUntil(page, 'the first click on activate asks for confirmation',
    (selector) => document.querySelector(selector).dataset.confirm === 'true', button(scene, ACTIVATE));
  await page.click(button(scene, ACTIVATE), { timeout: STEP_MS });
  await pageUntil(page, 'the confirmed activate is accepted and shown', ([selector, activate]) => {
    const cell = document.querySelector(`${selector} [data-col="cooperator"]`);
    const message = document.getElementById('message');
    return cell?.dataset.decision === String(activate) && message.dataset.kind === 'ok';
  }, [row(scene), ACTIVATE]);
  log(`activate confirmed, answered "${(await page.locator('#message').textContent()).trim()}"`);

  await pageUntil(page, 'autonomous and none are not offered, saying why; deactivate is',
    ([off, on]) => off.every((selector) => {
      const b = document.querySelector(selector);
      return b.disabled && b.title.includes('activate or deactivate only');
    }) && !document.querySelector(on).disabled,
    [[button(scene, AUTONOMOUS), button(scene, UNDECIDED)], button(scene, DEACTIVATE)]);
  const why = await page.locator(button(scene, AUTONOMOUS)).getAttribute('title');
  await pageUntil(page, 'the activate stands', ...cellIs(scene, 'cooperator', ACTIVATE));
  log(`autonomous and none are not offered: "${why}"; deactivate is`);
}

// As harness.mjs's `main`, for a run with no node or module of its own.
const watchdog = setTimeout(() => {
  console.error('FAIL: the panel run took longer than 60 s');
  process.exit(1);
}, 60_000);
const state = {};
let failed = null;
try {
  await run(state);
} catch (error) {
  failed = error;
}
if (state.browser) await state.browser.close().catch(() => {});
clearTimeout(watchdog);
if (failed) {
  console.error(`FAIL: ${failed instanceof Failure ? failed.message : failed.stack}`);
  process.exit(1);
}
log('the panel on the stack node: every step passed');
