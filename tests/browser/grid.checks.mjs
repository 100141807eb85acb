// The pixel grid as the textbook's table, and the page's state in its link: on
// models/zbuffer-exercise.scene (32 × 32, camera pixel) the grid shows the scene's own z, worked out
// here from the exercise's geometry; at 1920 × 1080 the whole grid (and the 50 × 50 one of
// zbuffer-exercise-50.scene) stands beside the picture with a readable font; a step marks the
// cells it wrote and rejected, as many as its text says; a copied link opens the same step with
// the same pixels in another page, and a link with bad values still opens the page, with a message.
// Works in pages of its own (h.newBrowser), at 1920 × 1080.

import path from 'node:path';

const LARGE = { width: 1920, height: 1080 };

// The exercise's surfaces: the rectangle (10..25) × (5..25) at z = 10 and the triangle
// (15, 15, 15), (30, 10, 5), (25, 25, 5), y up; pixel (column, row from the top) has its centre at
// (column + 0.5, 32 - row - 0.5).
const A = [15, 15, 15];
const B = [30, 10, 5];
const C = [25, 25, 5];
function triangleAt(x, y) {
  const u = [B[0] - A[0], B[1] - A[1], B[2] - A[2]];
  const v = [C[0] - A[0], C[1] - A[1], C[2] - A[2]];
  const area = u[0] * v[1] - u[1] * v[0];
  const wb = ((x - A[0]) * v[1] - (y - A[1]) * v[0]) / area;
  const wc = (u[0] * (y - A[1]) - u[1] * (x - A[0])) / area;
  return { weight: Math.min(wb, wc, 1 - wb - wc), z: A[2] + wb * u[2] + wc * v[2] };
}

export default async (h) => {
  const { check, assert } = h;
  const { browser, page } = await h.newBrowser({ viewport: LARGE });
  const frame = () => page.$eval('#canvas', (c) => Number(c.dataset.frame));
  const settledOn = (p, after) => p.waitForFunction((n) => {
    const c = document.querySelector('#canvas');
    return window.hsrView && window.hsrView.idle() && Number(c.dataset.frame) > n && c.dataset.state !== 'loading';
  }, after, { timeout: 30_000 });
  const idleOn = (p) => p.waitForFunction(() => window.hsrView && window.hsrView.idle()
    && document.querySelector('#canvas').dataset.state !== 'loading', null, { timeout: 30_000 });
  const andFrame = async (action) => {
    const before = await frame();
    await action();
    await settledOn(page, before);
    await idleOn(page);
  };
  const cellTexts = (p) => p.$$eval('#grid .cell', (all) => all.map((c) => c.textContent));
  const pixelsOf = (p) => p.$eval('#canvas', (c) => {
    const data = c.getContext('2d').getImageData(0, 0, c.width, c.height).data;
    let s = '';
    for (let i = 0; i < data.length; i += 4096) s += String.fromCharCode(...data.subarray(i, i + 4096));
    return `${c.width}x${c.height}:${btoa(s)}`;
  });
  // Where the grid and the picture are, and whether every cell's text fits its cell.
  const layout = (p) => p.evaluate(() => {
    window.scrollTo(0, 0);
    const box = (el) => {
      const r = el.getBoundingClientRect();
      return { left: r.left, top: r.top, right: r.right, bottom: r.bottom, width: r.width };
    };
    const cells = [...document.querySelectorAll('#grid .cell')];
    return {
      grid: box(document.querySelector('#grid')),
      canvas: box(document.querySelector('#canvas')),
      font: parseFloat(getComputedStyle(cells[0]).fontSize),
      clipped: cells.filter((c) => c.scrollWidth > c.clientWidth + 0.5 || c.scrollHeight > c.clientHeight + 0.5).length,
      viewport: { width: window.innerWidth, height: window.innerHeight },
    };
  });
  const assertOnScreenTogether = (l, what) => {
    const inside = (b) => b.left >= 0 && b.top >= 0 && b.right <= l.viewport.width && b.bottom <= l.viewport.height;
    assert(inside(l.grid), `${what}: the grid spans ${JSON.stringify(l.grid)} in ${JSON.stringify(l.viewport)}`);
    assert(inside(l.canvas), `${what}: the picture spans ${JSON.stringify(l.canvas)}`);
    assert(l.grid.left >= l.canvas.right - 1, `${what}: the grid is not beside the picture`);
    assert(l.canvas.width >= 200, `${what}: the picture is ${l.canvas.width} px wide`);
    assert(l.clipped === 0, `${what}: ${l.clipped} cells clip their text`);
  };
  const modelId = (name) => h.modelOption(page, name);

  try {
    await idleOn(page);
    const exercise = await modelId('zbuffer-exercise.scene');
    assert(exercise, 'zbuffer-exercise.scene is not in the model list');

    await check('the exercise\'s grid shows the scene\'s z: 10 on the rectangle, the triangle\'s z in front', async () => {
      if ((await page.$eval('#algorithm', (s) => s.value)) !== 'zbuffer') await andFrame(() => page.selectOption('#algorithm', 'zbuffer'));
      await andFrame(() => page.selectOption('#model', exercise));
      await page.waitForFunction(() => /^z \(/.test(document.querySelector('#grid-label').textContent)
        && document.querySelectorAll('#grid .cell').length === 32 * 32, null, { timeout: 30_000 });
      await idleOn(page);
      const cells = await cellTexts(page);
      let rectangle = 0;
      let triangle = 0;
      for (let row = 0; row < 32; ++row) {
        for (let column = 0; column < 32; ++column) {
          const x = column + 0.5;
          const y = 32 - row - 0.5;
          const text = cells[row * 32 + column];
          const inRectangle = x > 10 && x < 25 && y > 5 && y < 25;
          const t = triangleAt(x, y);
          if (Math.abs(t.weight) < 1e-6 || (t.weight > 0 && inRectangle && Math.abs(t.z - 10) < 1e-4)) continue;
          const where = `pixel ${column}, ${row}: "${text}"`;
          if (t.weight > 0 && (!inRectangle || t.z > 10)) {
            const shown = Number(text.replace('−', '-'));
            const tolerance = 0.5 * 10 ** (Math.floor(Math.log10(t.z)) - 2) + 1e-3;
            assert(Math.abs(shown - t.z) <= tolerance, `${where}, the triangle's z there is ${t.z}`);
            triangle += 1;
          } else if (inRectangle) {
            assert(text === '10', `${where}, the rectangle is at z = 10`);
            rectangle += 1;
          } else {
            assert(text === '−∞', `${where}, no surface there`);
          }
        }
      }
      assert(rectangle > 200 && triangle > 40, `${rectangle} rectangle and ${triangle} triangle pixels checked`);
      const sizes = await page.$eval('#width', (w) => [w.value, document.querySelector('#height').value, w.disabled]);
      assert(sizes[0] === '32' && sizes[1] === '32' && sizes[2], `width and height fields: ${sizes}`);
    });

    await check('at 1920×1080 the whole 32×32 grid stands beside the picture, font at least 10 px', async () => {
      const l = await layout(page);
      assertOnScreenTogether(l, '32×32');
      assert(l.font >= 10, `the grid's font is ${l.font} px`);
    });

    await check('a step marks the cells it wrote and rejected, as many as its text says', async () => {
      // Step 3 draws the triangle (steps 1 and 2 the rectangle's two triangles). The full render's number
      // box already reads 3, the last step: step forward first, so that typing 3 changes it.
      await andFrame(() => page.click('#step-forward'));
      await andFrame(async () => {
        await page.fill('#step-number', '3');
        await page.press('#step-number', 'Enter');
      });
      await page.waitForFunction(() => window.hsrView.lastResponse?.steps?.current === 3
        && document.querySelectorAll('#grid .cell').length === 32 * 32, null, { timeout: 30_000 });
      const stepText = await page.$eval('#step-text', (e) => e.textContent);
      const counted = stepText.match(/(\d+) pixels? written, (\d+) rejected/);
      assert(counted, `step text: ${stepText}`);
      const written = await page.$$eval('#grid .cell.written', (all) => all.length);
      const rejected = await page.$$eval('#grid .cell.rejected', (all) => all.length);
      assert(written === Number(counted[1]) && rejected === Number(counted[2]),
        `${written} cells marked written, ${rejected} rejected; the step says: ${stepText}`);
      assert(written > 0 && rejected > 0, `the triangle wrote ${written} and lost ${rejected} pixels`);
      const caption = await page.$eval('#grid-caption', (e) => e.textContent);
      assert(caption.includes(String(written)) && caption.includes(String(rejected)), `the grid's legend: ${caption}`);
      await page.evaluate(() => window.scrollTo(0, 0));
      await page.screenshot({ path: path.join(h.screenshotDir, 'viewer-exercise-table.png') });
      // Marked cells are the triangle's: their centres lie in it.
      const marks = await page.$$eval('#grid .cell', (all) => all.map((c, i) => (c.classList.contains('written')
        || c.classList.contains('rejected') ? i : -1)).filter((i) => i >= 0));
      for (const i of marks) {
        const t = triangleAt((i % 32) + 0.5, 32 - Math.floor(i / 32) - 0.5);
        assert(t.weight > -1e-6, `cell ${i % 32}, ${Math.floor(i / 32)} is marked outside the triangle`);
      }
    });

    await check('a copied link opens the same step with the same pixels in another browser', async () => {
      await page.selectOption('#grid-mode', 'colour');
      await page.click('#copy-link');
      await page.waitForFunction(() => document.querySelector('#copy-link').dataset.link, null, { timeout: 5_000 });
      const link = await page.$eval('#copy-link', (b) => b.dataset.link);
      assert(/[#&]step=3(&|$)/.test(link) && /grid=colour/.test(link), `the link: ${link}`);
      assert(await page.evaluate(() => window.location.href) === link, 'the address bar does not hold the link');
      const pixels = await pixelsOf(page);
      const cells = await cellTexts(page);
      const other = await h.newBrowser({ viewport: LARGE });
      try {
        const opened = await other.page.context().newPage();
        opened.on('pageerror', (e) => h.pageErrors.push(e.message));
        await opened.goto(link);
        await opened.waitForFunction(() => window.hsrView?.lastResponse?.steps?.current === 3
          && window.hsrView.idle() && document.querySelector('#canvas').dataset.state === 'ready'
          && document.querySelectorAll('#grid .cell').length === 32 * 32, null, { timeout: 30_000 });
        assert(await pixelsOf(opened) === pixels, 'the linked page\'s picture differs');
        const openedCells = await cellTexts(opened);
        assert(openedCells.join('|') === cells.join('|'), 'the linked page\'s grid differs');
        assert(await opened.$eval('#grid-mode', (s) => s.value) === 'colour', 'the grid mode is not the link\'s');
        assert(await opened.$eval('#model', (s) => s.value) === exercise, 'the model is not the link\'s');
      } finally {
        await other.browser.close();
      }
      await page.selectOption('#grid-mode', 'depth');
    });

    await check('colour cells show r, g and b whole', async () => {
      await page.selectOption('#grid-mode', 'colour');
      await page.waitForFunction(() => document.querySelector('#grid').classList.contains('colour'));
      const l = await layout(page);
      assert(l.clipped === 0, `${l.clipped} colour cells clip their text`);
      const first = await page.$eval('#grid .cell', (c) => c.innerText);
      assert(/^\d{1,3}\n\d{1,3}\n\d{1,3}$/.test(first), `a colour cell reads ${JSON.stringify(first)}`);
      await page.selectOption('#grid-mode', 'depth');
    });

    await check('at 1920×1080 the whole 50×50 grid stands beside the picture too, font at least 8 px', async () => {
      const fifty = await modelId('zbuffer-exercise-50.scene');
      assert(fifty, 'zbuffer-exercise-50.scene is not in the model list');
      await andFrame(() => page.selectOption('#model', fifty));
      await page.waitForFunction(() => /^z \(/.test(document.querySelector('#grid-label').textContent)
        && document.querySelectorAll('#grid .cell').length === 50 * 50, null, { timeout: 30_000 });
      await idleOn(page);
      const l = await layout(page);
      assertOnScreenTogether(l, '50×50');
      assert(l.font >= 8, `the grid's font is ${l.font} px`);
      const cells = await cellTexts(page);
      assert(cells.includes('20') && cells.includes('−∞'), 'the square at z = 20 or the empty pixels are missing');
    });

    await check('a link with bad values opens the page and says what it ignored', async () => {
      const opened = await page.context().newPage();
      try {
        const errors = [];
        opened.on('pageerror', (e) => errors.push(e.message));
        await opened.goto(`${h.serverUrl}#model=no/such.scene&algorithm=zbuffer&step=abc&width=-3&view=%3Cb%3E&yaw=x&grid=on`);
        await opened.waitForFunction(() => window.hsrView?.idle() && document.querySelector('#canvas').dataset.state === 'ready',
          null, { timeout: 30_000 });
        const message = await opened.$eval('#link-message', (e) => (e.hidden ? '' : e.textContent));
        for (const key of ['model', 'step', 'width', 'view', 'yaw', 'grid']) {
          assert(message.includes(key), `the message does not name ${key}: ${message}`);
        }
        assert(errors.length === 0, errors.join('; '));
      } finally {
        await opened.close();
      }
    });
  } finally {
    await browser.close();
  }
};
