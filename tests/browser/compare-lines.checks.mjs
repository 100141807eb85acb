// Compare with hidden-line plugins, and the whole reason of a refusal, in a page of its own: roberts
// beside appel shows the difference picture and a count of differing pixels; roberts beside a
// hidden-surface plugin shows a note naming both kinds instead of a picture; a model roberts refuses
// shows the server's whole message, wrapped and not cut, above the pictures.

export default async (h) => {
  const { check, assert } = h;
  const settled = (page, after) => page.waitForFunction((n) => {
    const c = document.querySelector('#canvas');
    return window.hsrView && window.hsrView.idle() && Number(c.dataset.frame) > n && c.dataset.state !== 'loading';
  }, after, { timeout: 20_000 });
  const idle = (page) => page.waitForFunction(() => window.hsrView && window.hsrView.idle()
    && document.querySelector('#canvas').dataset.state !== 'loading', null, { timeout: 20_000 });
  const frame = (page) => page.$eval('#canvas', (c) => Number(c.dataset.frame));
  const andFrame = async (page, action) => {
    const before = await frame(page);
    await action();
    await settled(page, before);
  };
  const shown = (page, selector) => page.$eval(selector, (e) => !e.closest('[hidden]') && e.getClientRects().length > 0)
    .catch(() => false);

  const own = await h.newBrowser();
  const { page } = own;
  try {
    await settled(page, 0);
    await andFrame(page, () => page.selectOption('#algorithm', 'roberts'));

    await check('compare: roberts beside appel shows the difference of the two line drawings', async () => {
      await page.selectOption('#compare-algorithm', 'appel');
      await andFrame(page, () => page.check('#compare-toggle'));
      assert(!(await page.$eval('#canvas', (c) => c.dataset.state === 'error')), await page.textContent('#error'));
      assert(await shown(page, '#compare-diff-image'), 'the difference picture is not shown');
      const count = (await page.textContent('#compare-diff')).replace(/\D/g, '');
      assert(count !== '', `differing pixels: '${await page.textContent('#compare-diff')}'`);
      assert(!(await shown(page, '#compare-note')), 'a note is shown for two hidden-line plugins');
      const options = await page.$$eval('#compare-algorithm option', (o) => o.map((e) => e.value));
      assert(options.includes('appel') && options.includes('zbuffer'), `compare offers ${options.join(', ')}`);
    });

    await check('compare: roberts beside zbuffer says why, with no stale picture', async () => {
      await andFrame(page, () => page.selectOption('#compare-algorithm', 'zbuffer'));
      assert(await shown(page, '#compare-note'), 'no note for a hidden-line plugin beside a hidden-surface one');
      const note = await page.textContent('#compare-note');
      assert(/roberts draws lines/.test(note) && /zbuffer fills surfaces/.test(note), `note: ${note}`);
      assert(!(await shown(page, '#compare-diff-image')), 'the old difference picture is still shown');
      assert(!(await page.$eval('#canvas', (c) => c.dataset.state === 'error')), await page.textContent('#error'));
      await page.click('.language-choice button[data-language="ru"]');
      await page.waitForFunction(() => /рисует линии/.test(document.querySelector('#compare-note').textContent), null,
        { timeout: 10_000 });
      await page.click('.language-choice button[data-language="en"]');
      await idle(page);
      await andFrame(page, () => page.uncheck('#compare-toggle'));
      assert(!(await shown(page, '#compare-note')), 'the note stays after compare is off');
    });

    await check('a model roberts refuses shows the whole reason, wrapped', async () => {
      const model = await h.modelOption(page, 'three-polygons.scene');
      assert(model, 'three-polygons.scene is not in the model list');
      await page.selectOption('#model', model);
      await page.waitForFunction(() => document.querySelector('#canvas').dataset.state === 'error', null, { timeout: 20_000 });
      await idle(page);
      assert(await shown(page, '#refusal'), 'no refusal box');
      const whole = await page.textContent('#error');
      const reason = await page.textContent('#refusal .refusal-text');
      assert(reason === whole && reason.length > 0, `box: '${reason}', error line: '${whole}'`);
      const cut = await page.$eval('#refusal .refusal-text', (e) => e.scrollWidth > e.clientWidth + 0.5);
      assert(!cut, 'the reason is cut');
      assert(/roberts/.test(await page.textContent('#refusal .refusal-title')), 'the box does not name the plugin');
      await page.evaluate(() => window.scrollTo(0, 0));
      await page.screenshot({ path: `${h.screenshotDir}/viewer-refusal.png` });
      const boxes = model.replace(/[^/]*$/, 'boxes.scene');
      await andFrame(page, () => page.selectOption('#model', boxes));
      assert(!(await shown(page, '#refusal')), 'the refusal box stays after a model that draws');
    });
  } finally {
    await own.browser.close();
  }
};
