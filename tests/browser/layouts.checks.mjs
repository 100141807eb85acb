// The page at the sizes of a lecture: a 1280×720 projector, a 1920×1080 screen and a 1024×768
// tablet with touch, each in a context of a browser of their own (viewer.test.mjs runs this module with its
// harness h). At each size the picture is on screen on load and no wider than the window, the step
// buttons come into view with the picture still mostly in view, and nothing overflows sideways. On
// the tablet a tap on "step forward" steps and a one-finger drag on the picture orbits the camera.
// The export of a range of steps (step-export.js) shows the hsr render command for the range.
// Screenshots: viewer-layout-<name>.png, the window as it is with the step buttons in view.

import path from 'node:path';

const LAYOUTS = [
  { name: '1280x720', viewport: { width: 1280, height: 720 } },
  { name: '1920x1080', viewport: { width: 1920, height: 1080 } },
  { name: 'tablet-1024x768', viewport: { width: 1024, height: 768 }, hasTouch: true, isMobile: true, touch: true },
];

export default async (h) => {
  const { check, assert } = h;
  // One browser, a context of it for each size: launching a browser costs seconds.
  let shared = null;
  try {
    shared = await h.newBrowser();
  } catch (e) {
    await check('layouts: a browser of their own starts', async () => { throw e; });
    return;
  }

  for (const layout of LAYOUTS) {
    let own = null;
    try {
      await check(`layout ${layout.name}: the picture on screen, the step bar in reach, no sideways overflow`, async () => {
        const context = await shared.browser.newContext({
          viewport: layout.viewport, hasTouch: Boolean(layout.hasTouch), isMobile: Boolean(layout.isMobile),
        });
        own = { context, page: await context.newPage() };
        const { page } = own;
        page.setDefaultTimeout(10_000);
        page.on('pageerror', (e) => h.pageErrors.push(e.message));
        await page.goto(h.printedUrl);
        await page.waitForFunction(() => {
          const c = document.querySelector('#canvas');
          return window.hsrView && window.hsrView.idle() && Number(c.dataset.frame) > 0 && c.dataset.state !== 'loading'
            && !document.querySelector('#steps').hidden;
        }, null, { timeout: 20_000 });
        const onLoad = await page.evaluate(() => {
          const r = document.querySelector('#canvas').getBoundingClientRect();
          return {
            left: r.left, right: r.right, top: r.top, bottom: r.bottom, width: r.width,
            innerWidth: window.innerWidth, innerHeight: window.innerHeight,
            scrollWidth: document.documentElement.scrollWidth,
          };
        });
        assert(onLoad.width > 100, `the picture is ${onLoad.width} px wide`);
        assert(onLoad.left >= 0 && onLoad.right <= onLoad.innerWidth,
          `the picture spans ${onLoad.left}–${onLoad.right} px of a ${onLoad.innerWidth} px window`);
        assert(onLoad.top >= 0 && onLoad.top < onLoad.innerHeight / 3,
          `the picture starts at ${onLoad.top} px of a ${onLoad.innerHeight} px window`);
        assert(onLoad.scrollWidth <= onLoad.innerWidth,
          `the page is ${onLoad.scrollWidth} px wide in a ${onLoad.innerWidth} px window`);
        // The step buttons brought into view: the picture stays at least half in view.
        await page.$eval('#step-forward', (b) => b.scrollIntoView({ block: 'nearest' }));
        const inReach = await page.evaluate(() => {
          const c = document.querySelector('#canvas').getBoundingClientRect();
          const b = document.querySelector('#step-forward').getBoundingClientRect();
          const seen = Math.max(0, Math.min(c.bottom, window.innerHeight) - Math.max(c.top, 0));
          return { seen: seen / c.height, buttonTop: b.top, buttonBottom: b.bottom, innerHeight: window.innerHeight };
        });
        assert(inReach.buttonTop >= 0 && inReach.buttonBottom <= inReach.innerHeight,
          `the step buttons at ${inReach.buttonTop}–${inReach.buttonBottom} px of ${inReach.innerHeight}`);
        assert(inReach.seen >= 0.5, `with the step buttons in view ${Math.round(inReach.seen * 100)}% of the picture is`);
        await page.screenshot({ path: path.join(h.screenshotDir, `viewer-layout-${layout.name}.png`) });
      });

      if (layout.touch) {
        await check(`layout ${layout.name}: a tap on step forward steps, a touch drag orbits`, async () => {
          assert(own, 'no page');
          const { page } = own;
          const frame = () => page.$eval('#canvas', (c) => Number(c.dataset.frame));
          const settledAfter = (n) => page.waitForFunction((k) => {
            const c = document.querySelector('#canvas');
            return window.hsrView.idle() && Number(c.dataset.frame) > k && c.dataset.state !== 'loading';
          }, n, { timeout: 20_000 });
          let before = await frame();
          await page.tap('#step-first');
          await settledAfter(before);
          before = await frame();
          await page.tap('#step-forward');
          await settledAfter(before);
          const step = await page.evaluate(() => window.hsrView.lastRequest?.step);
          assert(step === 2, `after a tap on step first and one on step forward the step is ${step}`);

          const yawBefore = await page.evaluate(() => JSON.stringify(window.hsrView.camera()));
          const box = await page.$eval('#canvas', (c) => {
            const r = c.getBoundingClientRect();
            return { x: r.left + r.width / 2, y: r.top + r.height / 2 };
          });
          const cdp = await page.context().newCDPSession(page);
          const touch = (type, x, y) => cdp.send('Input.dispatchTouchEvent', {
            type, touchPoints: type === 'touchEnd' ? [] : [{ x: Math.round(x), y: Math.round(y), id: 1 }],
          });
          before = await frame();
          await touch('touchStart', box.x, box.y);
          for (let k = 1; k <= 8; ++k) await touch('touchMove', box.x + 10 * k, box.y + 3 * k);
          await touch('touchEnd', box.x + 80, box.y + 24);
          await settledAfter(before);
          const yawAfter = await page.evaluate(() => JSON.stringify(window.hsrView.camera()));
          assert(yawAfter !== yawBefore, `the camera is still ${yawBefore} after a touch drag`);
          const scrolledX = await page.evaluate(() => window.scrollX);
          assert(scrolledX === 0, `the drag scrolled the page ${scrolledX} px sideways`);
        });
      }

      if (layout.name === '1280x720') {
        await check('export steps: the step bar shows the hsr render command for the range', async () => {
          assert(own, 'no page');
          const { page } = own;
          await page.click('#step-export summary');
          await page.fill('#step-export-from', '2');
          await page.fill('#step-export-to', '5');
          const command = await page.$eval('#step-export-command', (e) => e.textContent);
          assert(/^hsr render \S+ -a zbuffer\b.* --width \d+ --height \d+ .*--step 2\.\.5 -o 'step-%03d\.png'$/.test(command),
            `command: ${command}`);
          assert(!/--step \d+ .*--step/.test(command), `two --step in: ${command}`);
          await page.fill('#step-export-to', '1');
          assert(await page.$eval('#step-export-command', (e) => e.textContent) === '', 'a backward range still has a command');
          assert(await page.$eval('#step-export-copy', (b) => b.disabled), 'copy is enabled for a backward range');
          assert(/ends before it starts/.test(await page.$eval('#step-export-note', (e) => e.textContent)), 'no note for a backward range');
          await page.fill('#step-export-to', '1002');
          assert(/at most 1000/.test(await page.$eval('#step-export-note', (e) => e.textContent)), 'no note for 1001 steps');
        });
      }
    } finally {
      if (own) await own.context.close();
    }
  }
  await shared.browser.close();
};
