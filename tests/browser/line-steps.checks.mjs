// Hidden-line steps that show what hides what (line_steps.js), in pages of their own: on boxes.scene
// with appel, a step where an edge's QI changes draws that edge thick (the overlay's pixels beside
// its projection are painted), the key beneath the steps speaks Appel's words, the face and edge
// numbers appear when asked for, and every colour of the key stands out 4.5:1 from the picture's
// background in the light and the dark page theme.

// WCAG's relative luminance and contrast ratio of two sRGB colours given as [r, g, b] (0-255).
function luminance([r, g, b]) {
  const channel = (v) => {
    const c = v / 255;
    return c <= 0.03928 ? c / 12.92 : ((c + 0.055) / 1.055) ** 2.4;
  };
  return 0.2126 * channel(r) + 0.7152 * channel(g) + 0.0722 * channel(b);
}
function contrast(a, b) {
  const [hi, lo] = [luminance(a), luminance(b)].sort((x, y) => y - x);
  return (hi + 0.05) / (lo + 0.05);
}
function rgbOf(hex) {
  const m = /^#([0-9a-f]{2})([0-9a-f]{2})([0-9a-f]{2})$/i.exec(hex.trim());
  if (!m) throw new Error(`not a #rrggbb colour: ${hex}`);
  return [1, 2, 3].map((i) => parseInt(m[i], 16));
}

export default async (h) => {
  const { check, assert } = h;

  // The page's own frames: wait until the page is idle with a frame newer than `after`.
  const settled = (page, after) => page.waitForFunction((n) => {
    const c = document.querySelector('#canvas');
    return window.hsrView && window.hsrView.idle() && Number(c.dataset.frame) > n && c.dataset.state !== 'loading';
  }, after, { timeout: 20_000 });
  const frame = (page) => page.$eval('#canvas', (c) => Number(c.dataset.frame));
  const andFrame = async (page, action) => {
    const before = await frame(page);
    await action();
    await settled(page, before);
  };

  // A page with appel on boxes.scene, stopped at the first step where an edge's QI changes.
  async function appelAtQiChange(options) {
    const own = await h.newBrowser(options);
    const { page } = own;
    await settled(page, 0);
    await andFrame(page, () => page.selectOption('#algorithm', 'appel'));
    const request = await page.evaluate(() => window.hsrView.lastRequest);
    let step = null;
    for (let k = 1; k <= 400 && step === null; k += 1) {
      const answer = await fetch(new URL('api/frame', h.serverUrl), {
        method: 'POST', headers: h.apiHeaders, body: JSON.stringify({ ...request, step: k, picture: false }) });
      const steps = (await answer.json()).steps;
      if (steps.type === 'qi-change') step = k;
      if (steps.current < k) break;
    }
    assert(step !== null, 'appel on boxes.scene has no QI change in its first 400 steps');
    await andFrame(page, async () => {
      await page.fill('#step-number', String(step));
      await page.dispatchEvent('#step-number', 'change');
    });
    return { ...own, step };
  }

  // What the overlay shows: the count of painted pixels, and whether those beside the edge's
  // projection are painted (the edge drawn thick).
  const overlayState = (page) => page.evaluate(() => {
    const overlay = document.querySelector('#overlay');
    const data = overlay.getContext('2d').getImageData(0, 0, overlay.width, overlay.height).data;
    let painted = 0;
    for (let i = 3; i < data.length; i += 4) painted += data[i] > 0 ? 1 : 0;
    const figure = window.hsrView.lastResponse.steps.figure;
    const scale = overlay.width / overlay.getBoundingClientRect().width;
    const [x0, y0, x1, y1] = figure.edge.lines[0];
    const length = Math.hypot(x1 - x0, y1 - y0);
    const [nx, ny] = [-(y1 - y0) / length, (x1 - x0) / length];
    const alpha = (x, y) => {
      const px = Math.round(x), py = Math.round(y);
      if (px < 0 || py < 0 || px >= overlay.width || py >= overlay.height) return 255;
      return data[4 * (py * overlay.width + px) + 3];
    };
    let samples = 0, thick = 0;
    for (let t = 0.15; t <= 0.85; t += 0.05) {
      const x = x0 + t * (x1 - x0), y = y0 + t * (y1 - y0);
      samples += 1;
      // 2.5 display pixels to either side of the line's centre: inside the edge's band, 11 wide.
      if (alpha(x + 2.5 * scale * nx, y + 2.5 * scale * ny) > 0 && alpha(x - 2.5 * scale * nx, y - 2.5 * scale * ny) > 0) {
        thick += 1;
      }
    }
    return { painted, samples, thick, length, edge: figure.edge.index };
  });

  // One page for the light theme (the first three checks), one for the dark.
  let light = null;
  try {
    await check('line steps: appel\'s QI change draws the edge under test thick, with its number', async () => {
      light = await appelAtQiChange({ colorScheme: 'light' });
      const { page, step } = light;
      const stepText = await page.$eval('#step-text', (e) => e.textContent);
      assert(/QI \d+ to \d+/.test(stepText), `step ${step}: ${stepText}`);
      const state = await overlayState(page);
      assert(state.length > 10, `the edge is ${state.length} pixels long in the picture`);
      assert(state.thick === state.samples,
        `the overlay is thick at ${state.thick} of ${state.samples} points along edge ${state.edge}`);
      const key = await page.$eval('#line-step-key', (e) => (e.hidden ? '' : e.textContent));
      for (const words of ['edge under test', 'contour line crossed', 'visible part, QI = 0', 'hidden part, QI > 0',
        'quantitative invisibility']) {
        assert(key.includes(words), `the key does not say "${words}": ${key}`);
      }
      assert(await page.$eval('#steps .step-key', (e) => getComputedStyle(e).display === 'none'),
        'the general key (subject, written, ...) is still shown');
      await page.screenshot({ path: `${h.screenshotDir}/viewer-appel-step.png`, fullPage: true });
    });

    await check('line steps: face and edge numbers appear on the picture when asked for', async () => {
      assert(light, 'no page at a QI change');
      const { page } = light;
      const before = await overlayState(page);
      await page.check('#line-labels');
      const after = await overlayState(page);
      assert(after.painted > before.painted + 200, `the overlay painted ${before.painted} pixels, then ${after.painted}`);
      const key = await page.$eval('#line-step-key', (e) => e.textContent);
      assert(key.includes('face number'), `the key does not explain the numbers: ${key}`);
      await page.uncheck('#line-labels');
      assert((await overlayState(page)).painted === before.painted, 'unchecking did not take the numbers away');
    });

    await check('line steps: in Russian the key speaks of количественная невидимость', async () => {
      assert(light, 'no page at a QI change');
      const { page } = light;
      await page.click('button[data-language="ru"]');
      await page.waitForFunction(() => /количественная невидимость меняется/.test(
        document.querySelector('#step-text').textContent), null, { timeout: 20_000 });
      await settled(page, 0);
      const key = await page.$eval('#line-step-key', (e) => e.textContent);
      for (const words of ['проверяемое ребро', 'контурная линия', 'КН = 0', 'количественная невидимость']) {
        assert(key.includes(words), `the key does not say «${words}»: ${key}`);
      }
      const stepText = await page.$eval('#step-text', (e) => e.textContent);
      assert(/количественная невидимость меняется с \d+ на \d+/.test(stepText), `the step text: ${stepText}`);
      await page.click('button[data-language="en"]');
      await page.waitForFunction(() => /QI \d+ to \d+/.test(document.querySelector('#step-text').textContent), null,
        { timeout: 20_000 });
    });

    // Each colour of the key against the picture's background, in the page's theme.
    const checkContrast = async (page, colorScheme) => {
      const found = await page.evaluate(() => ({
        background: window.hsrView.lastResponse.steps.figure.background,
        swatches: [...document.querySelectorAll('#line-step-key .swatch')]
          .map((s) => [s.dataset.kind, s.style.getPropertyValue('--swatch')]),
        dark: matchMedia('(prefers-color-scheme: dark)').matches,
      }));
      assert(found.dark === (colorScheme === 'dark'), `the page's theme is not ${colorScheme}`);
      assert(found.swatches.length >= 4, `${found.swatches.length} colours in the key`);
      for (const [kind, color] of found.swatches) {
        const ratio = contrast(rgbOf(color), found.background);
        assert(ratio >= 4.5, `${kind} ${color} on rgb(${found.background}): ${ratio.toFixed(2)}:1`);
      }
    };
    await check('line steps: each colour of the key has 4.5:1 contrast on the picture (light theme)', async () => {
      assert(light, 'no page at a QI change');
      await checkContrast(light.page, 'light');
    });
    await check('line steps: each colour of the key has 4.5:1 contrast on the picture (dark theme)', async () => {
      const dark = await appelAtQiChange({ colorScheme: 'dark' });
      try {
        await checkContrast(dark.page, 'dark');
      } finally {
        await dark.browser.close();
      }
    });
  } finally {
    await light?.browser.close();
  }
};
