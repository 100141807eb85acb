// Steps at a lecture's pace (docs/viewer.md, "Steps"): the step bar moves by the units of the run's
// outline (next culled node, next phase, next level), shows the step count with the first picture
// without asking for step 1, draws node boxes at least 2 CSS pixels wide, and fills the theory
// pane's worked example with a button that shows a phase's first step. In a page of its own.

export default async (h) => {
  const { check, assert } = h;
  const { browser, page } = await h.newBrowser();
  const requests = [];
  page.on('request', (r) => {
    if (r.method() !== 'POST') return;
    let body = null;
    try {
      body = JSON.parse(r.postData() || 'null');
    } catch {
      // not JSON
    }
    requests.push({ path: new URL(r.url()).pathname, body });
  });

  const frameNumber = () => page.$eval('#canvas', (c) => Number(c.dataset.frame));
  const settled = async (after, timeout = 30_000) => page.waitForFunction((n) => {
    const c = document.querySelector('#canvas');
    return window.hsrView && window.hsrView.idle() && Number(c.dataset.frame) > n && c.dataset.state !== 'loading';
  }, after, { timeout });
  const andFrame = async (action, timeout) => {
    const before = await frameNumber();
    await action();
    await settled(before, timeout);
  };
  const lastSteps = () => page.evaluate(() => window.hsrView.lastResponse?.steps ?? null);
  const outlineCame = (timeout = 30_000) => page.waitForFunction(() => window.hsrView?.outline()
    && document.querySelector('#step-by').options.length > 1, null, { timeout });
  const setSize = async (side) => {
    for (const field of ['#width', '#height']) {
      if (await page.$eval(field, (e) => e.value) === String(side)) continue;
      await page.fill(field, String(side));
      await andFrame(() => page.press(field, 'Tab'), 120_000);
    }
  };
  const stepRequests = () => requests.filter((r) => r.path === '/api/frame' && r.body && r.body.step !== null
    && r.body.step !== undefined);

  try {
    await settled(0);
    await setSize(192);

    await check('pace: the step count shows with the first picture, with no request for step 1', async () => {
      requests.length = 0;
      await andFrame(() => page.selectOption('#algorithm', 'octree-zbuffer'));
      // Leaves of one triangle seen from close by: some nodes lie outside the view and are culled.
      await page.fill('#params [name="leaf-triangles"]', '1');
      await andFrame(() => page.press('#params [name="leaf-triangles"]', 'Tab'));
      await page.fill('#zoom', '3');
      await andFrame(() => page.press('#zoom', 'Tab'));
      await page.waitForFunction(() => window.hsrView.outline()?.firsts['type:node-culled']
        && document.querySelector('#step-by option[value="type:node-culled"]'), null, { timeout: 30_000 });
      await page.waitForFunction(() => /\d/.test(document.querySelector('#step-total').textContent));
      const total = (await page.$eval('#step-total', (e) => e.textContent)).replace(/\D/g, '');
      const outline = await page.evaluate(() => window.hsrView.outline().total);
      assert(Number(total) === outline, `the bar says ${total} steps, the outline ${outline}`);
      assert(stepRequests().length === 0, `step frames asked for: ${JSON.stringify(stepRequests().map((r) => r.body.step))}`);
      const outlines = requests.filter((r) => r.path === '/api/steps').length;
      assert(outlines >= 1 && outlines <= 3, `${outlines} outlines asked for three views`);
      const shown = await page.evaluate(() => window.hsrView.lastRequest.step);
      assert(shown === null, `step ${shown} is shown, not the full render`);
    });

    await check('pace: next culled node lands on a culled node, and back returns', async () => {
      const culled = await page.evaluate(() => window.hsrView.outline().firsts['type:node-culled']?.step ?? null);
      assert(culled !== null, 'the outline of octree-zbuffer on boxes.scene has no culled node');
      await page.selectOption('#step-by', 'type:node-culled');
      await andFrame(() => page.click('#step-unit-forward'));
      let steps = await lastSteps();
      assert(steps.current === culled && steps.type === 'node-culled',
        `step ${steps.current} (${steps.type}: ${steps.text}), the first culled node is ${culled}`);
      await andFrame(() => page.keyboard.press('Shift+ArrowRight'));
      steps = await lastSteps();
      assert(steps.type === 'node-culled' && steps.current > culled, `Shift+→ gave step ${steps.current} (${steps.type})`);
      await andFrame(() => page.click('#step-unit-back'));
      steps = await lastSteps();
      assert(steps.current === culled && steps.type === 'node-culled', `back gave step ${steps.current}, not ${culled}`);
      await andFrame(() => page.keyboard.press('ArrowRight'));
      assert((await lastSteps()).current === culled + 1, '→ does not step by one');
      await andFrame(() => page.keyboard.press('ArrowLeft'));
    });

    await check('pace: node boxes are at least 2 CSS pixels wide', async () => {
      await page.selectOption('#step-by', 'type:node-visited');
      const measured = [];
      for (let tries = 0; tries < 8 && measured.length < 4; tries += 1) {
        await andFrame(() => page.click('#step-unit-forward'));
        measured.push(...await page.evaluate(() => {
          const steps = window.hsrView.lastResponse.steps;
          const overlay = document.querySelector('#overlay');
          const rect = overlay.getBoundingClientRect();
          const factor = overlay.width / window.hsrView.lastResponse.width;
          const data = overlay.getContext('2d').getImageData(0, 0, overlay.width, overlay.height).data;
          const drawn = (x, y) => y >= 0 && y < overlay.height && data[4 * (y * overlay.width + x) + 3] > 16;
          const found = [];
          // Across the middle of each horizontal side inside the picture: the rows drawn there.
          for (const [x0, y0, x1, y1] of steps.lines) {
            if (Math.abs(y1 - y0) > 0.01 || Math.abs(x1 - x0) < 6 || y0 < 3 || y0 > window.hsrView.lastResponse.height - 3) continue;
            const x = Math.round(((x0 + x1) / 2) * factor);
            let top = Math.round(y0 * factor);
            if (!drawn(x, top)) top -= 1;
            if (!drawn(x, top)) continue;
            let bottom = top;
            while (drawn(x, top - 1)) top -= 1;
            while (drawn(x, bottom + 1)) bottom += 1;
            found.push(((bottom - top + 1) * rect.height) / overlay.height);
          }
          return found;
        }));
      }
      assert(measured.length > 0, 'no side of a node\'s box to measure on the overlay');
      assert(Math.min(...measured) >= 1.9, `box sides ${measured.map((w) => w.toFixed(2)).join(', ')} CSS px wide`);
    });

    await check('pace: next level and next phase change the level and phase shown', async () => {
      const units = await page.$$eval('#step-by option', (options) => options.map((o) => o.value));
      assert(units.includes('level'), `no "next level" among ${units.join(', ')}`);
      await andFrame(() => page.click('#step-first'));
      await page.selectOption('#step-by', 'level');
      const levelOf = () => page.$eval('#step-where', (e) => (e.textContent.match(/level (\d+)|уровень (\d+)/) || [''])[0]);
      const before = await levelOf();
      await andFrame(() => page.click('#step-unit-forward'));
      const after = await levelOf();
      assert(before !== after, `the level stayed "${before}"`);
      if (units.includes('phase')) {
        await page.selectOption('#step-by', 'phase');
        const phaseBefore = (await lastSteps()).phase;
        await andFrame(() => page.click('#step-unit-forward'));
        const phaseAfter = (await lastSteps()).phase;
        assert(phaseBefore !== phaseAfter, `the phase stayed ${phaseBefore}`);
      }
      await page.selectOption('#step-by', 'step');
    });

    await check('pace: the worked example is filled from the outline and its button shows that step', async () => {
      await page.click('#theory-toggle');
      await page.waitForFunction(() => document.querySelector('#theory').textContent.trim().length > 0);
      await page.evaluate(() => {
        if (!document.querySelector('#theory div.worked-example')) {
          const block = document.createElement('div');
          block.className = 'worked-example';
          document.querySelector('#theory').append(block);
        }
        window.hsrView.showOutline();
      });
      await page.waitForFunction(() => document.querySelector('#theory div.worked-example table'));
      const { text, buttons } = await page.$eval('#theory div.worked-example', (e) => ({
        text: e.textContent, buttons: [...e.querySelectorAll('button[data-step]')].map((b) => Number(b.dataset.step)),
      }));
      const total = await page.evaluate(() => window.hsrView.outline().total);
      assert(text.includes('boxes.scene'), `the model is not named: ${text.slice(0, 200)}`);
      assert(text.replace(/[\s,\u00a0]/g, '').includes(String(total)), `the step count ${total} is missing: ${text.slice(0, 200)}`);
      assert(buttons.length > 0, 'no first step to show');
      const target = buttons[buttons.length - 1];
      await andFrame(() => page.click(`#theory div.worked-example button[data-step="${target}"]`));
      assert((await lastSteps()).current === target, `the button showed step ${(await lastSteps()).current}, not ${target}`);
      await page.click('#theory-toggle');
    });

    await check('pace: deep-monkeys.scene, hundreds of thousands of steps, reaches its first culled node at once', async () => {
      const option = await page.$$eval('#model option', (options) => options.map((o) => o.value).find((v) => v.endsWith('deep-monkeys.scene')));
      if (!option) return;  // the models folder served has no such scene
      await setSize(96);
      await andFrame(() => page.selectOption('#model', option), 120_000);
      if (await page.$eval('#canvas', (c) => c.dataset.state === 'error')) return;  // its meshes are not fetched
      await outlineCame(120_000);
      const culled = await page.evaluate(() => window.hsrView.outline().firsts['type:node-culled']?.step ?? null);
      assert(culled !== null, 'no culled node in deep-monkeys.scene');
      await page.selectOption('#step-by', 'type:node-culled');
      await andFrame(() => page.click('#step-unit-forward'), 120_000);
      const steps = await lastSteps();
      assert(steps.current === culled && steps.type === 'node-culled', `step ${steps.current}: ${steps.type}`);
    });
  } finally {
    await browser.close();
  }
};
