// The scene editor: opened on a .scene model it holds that file's text; a typed change renders
// (moving the exercise triangle's left corner to x = 5 puts the triangle, in front of the
// rectangle there, over a pixel the rectangle alone covered, as the geometry worked out here
// says); a broken line shows the server's message beside that line number and the picture stays;
// a starting point loads its file (boxes.scene with its meshes); the download gives the text. Works in a page of its own.

import fs from 'node:fs';
import path from 'node:path';

// Pixel (column 12, row 16 from the top) of the 32 × 32 exercise has its centre at (12.5, 15.5), y up.
const PROBE = { column: 12, row: 16, x: 12.5, y: 15.5 };

// The barycentric weights' minimum and the depth of triangle (a, b, c) at (x, y).
function triangleAt([a, b, c], x, y) {
  const u = [b[0] - a[0], b[1] - a[1], b[2] - a[2]];
  const v = [c[0] - a[0], c[1] - a[1], c[2] - a[2]];
  const area = u[0] * v[1] - u[1] * v[0];
  const wb = ((x - a[0]) * v[1] - (y - a[1]) * v[0]) / area;
  const wc = (u[0] * (y - a[1]) - u[1] * (x - a[0])) / area;
  return { weight: Math.min(wb, wc, 1 - wb - wc), z: a[2] + wb * u[2] + wc * v[2] };
}

export default async (h) => {
  const { check, assert } = h;
  const { browser, page } = await h.newBrowser();
  const exerciseText = fs.readFileSync(path.join(h.sourceDir, 'models', 'zbuffer-exercise.scene'), 'utf8');
  const frame = () => page.$eval('#canvas', (c) => Number(c.dataset.frame));
  const idle = () => page.waitForFunction(() => window.hsrView && window.hsrView.idle()
    && document.querySelector('#canvas').dataset.state !== 'loading', null, { timeout: 30_000 });
  const andFrame = async (action) => {
    const before = await frame();
    await action();
    await page.waitForFunction((n) => {
      const c = document.querySelector('#canvas');
      return window.hsrView.idle() && Number(c.dataset.frame) > n && c.dataset.state === 'ready';
    }, before, { timeout: 30_000 });
  };
  // The colour of image pixel (column, row) of a 32 × 32 picture, however large the canvas shows it.
  const probe = () => page.$eval('#canvas', (c, p) => {
    const x = Math.floor(((p.column + 0.5) * c.width) / 32);
    const y = Math.floor(((p.row + 0.5) * c.height) / 32);
    const [r, g, b] = c.getContext('2d').getImageData(x, y, 1, 1).data;
    return { r, g, b };
  }, PROBE);
  const allPixels = () => page.$eval('#canvas', (c) => {
    const data = c.getContext('2d').getImageData(0, 0, c.width, c.height).data;
    let s = '';
    for (let i = 0; i < data.length; i += 4096) s += String.fromCharCode(...data.subarray(i, i + 4096));
    return `${c.width}x${c.height}:${btoa(s)}`;
  });
  const editorText = () => page.$eval('#scene-text', (t) => t.value);
  const editorUploads = () => page.$$eval('#model option', (all) => all.filter((o) => o.value.endsWith('scene-editor.scene')).length);

  try {
    await idle();
    // Other checks' pages (editor-russian.checks.mjs) may have left editor uploads of their own,
    // which this page's list shows once it is next filled: count them on the server.
    const served = await (await fetch(new URL('api/models', h.serverUrl), { headers: h.apiHeaders })).json();
    const othersUploads = served.models.filter((m) => m.id.endsWith('scene-editor.scene')).length;
    const exercise = await h.modelOption(page, 'zbuffer-exercise.scene');
    assert(exercise, 'zbuffer-exercise.scene is not in the model list');
    if ((await page.$eval('#algorithm', (s) => s.value)) !== 'zbuffer') await andFrame(() => page.selectOption('#algorithm', 'zbuffer'));
    await andFrame(() => page.selectOption('#model', exercise));

    await check('the scene editor opens with the .scene model\'s text', async () => {
      await page.click('#scene-editor summary');
      await page.waitForFunction(() => document.querySelector('#scene-text').value.length > 0, null, { timeout: 10_000 });
      assert(await editorText() === exerciseText, 'the editor does not hold models/zbuffer-exercise.scene');
      const numbers = await page.$$eval('#scene-lines span', (all) => all.length);
      assert(numbers === exerciseText.split('\n').length, `${numbers} line numbers for ${exerciseText.split('\n').length} lines`);
    });

    let goodPixels = null;
    await check('a typed change renders: the moved triangle corner covers the probed pixel', async () => {
      const before = await probe();
      const rectangle = PROBE.x > 10 && PROBE.x < 25 && PROBE.y > 5 && PROBE.y < 25;
      const original = triangleAt([[15, 15, 15], [30, 10, 5], [25, 25, 5]], PROBE.x, PROBE.y);
      assert(rectangle && original.weight < 0, 'the probe is meant to lie on the rectangle alone');
      assert(before.b > before.r + 60, `before the edit the pixel is not the rectangle's blue: ${JSON.stringify(before)}`);
      const moved = triangleAt([[5, 15, 15], [30, 10, 5], [25, 25, 5]], PROBE.x, PROBE.y);
      assert(moved.weight > 0 && moved.z > 10, `the moved triangle is not in front at the probe: ${JSON.stringify(moved)}`);
      const edited = exerciseText.replace('vertex 15 15 15', 'vertex 5 15 15');
      assert(edited !== exerciseText, 'the exercise has no vertex 15 15 15');
      await andFrame(() => page.fill('#scene-text', edited));
      const model = await page.evaluate(() => window.hsrView.lastRequest?.model || document.querySelector('#model').value);
      assert(/^upload\/.*scene-editor\.scene$/.test(model), `the page renders ${model}, not the editor's upload`);
      const after = await probe();
      assert(after.r > after.b + 60, `after the edit the pixel is not the triangle's red: ${JSON.stringify(after)}`);
      goodPixels = await allPixels();
    });

    await check('a broken line shows its error beside that line number, and the picture stays', async () => {
      const good = await editorText();
      const lines = good.split('\n');
      const index = lines.findIndex((l) => l.trim() === 'vertex 30 10 5');
      assert(index >= 0, 'no line "vertex 30 10 5"');
      lines[index] = '  vertex 30 10';
      await page.fill('#scene-text', lines.join('\n'));
      await page.waitForFunction(() => !document.querySelector('#scene-line-error').hidden, null, { timeout: 30_000 });
      await idle();
      const shown = await page.evaluate(() => {
        const error = document.querySelector('#scene-line-error');
        const bad = document.querySelector('#scene-lines span.bad');
        return {
          line: error.dataset.line, text: error.textContent,
          errorTop: error.getBoundingClientRect().top, badTop: bad?.getBoundingClientRect().top,
          badLine: bad?.dataset.line,
        };
      });
      assert(shown.line === String(index + 1) && shown.badLine === String(index + 1),
        `the error is on line ${shown.line} (marked ${shown.badLine}), the broken line is ${index + 1}: ${shown.text}`);
      assert(Math.abs(shown.errorTop - shown.badTop) < 4, `the message is at ${shown.errorTop}, its line at ${shown.badTop}`);
      assert(shown.text.startsWith(`${index + 1}: `) && shown.text.length > 6, `message: "${shown.text}"`);
      assert(await allPixels() === goodPixels, 'the picture changed after a broken edit');
      await andFrame(() => page.fill('#scene-text', good));
      assert(await page.$eval('#scene-line-error', (e) => e.hidden), 'the error stays after the line is mended');
    });

    await check('a starting point loads its file and renders it', async () => {
      const three = fs.readFileSync(path.join(h.sourceDir, 'models', 'three-polygons.scene'), 'utf8');
      await andFrame(() => page.selectOption('#scene-start', 'three-polygons.scene'));
      assert(await editorText() === three, 'the editor does not hold models/three-polygons.scene');
      assert(await allPixels() !== goodPixels, 'the picture did not change to the three polygons');
      const uploads = await editorUploads() - othersUploads;
      assert(uploads === 1, `${uploads} editor uploads of this page in the model list, not one`);
      // boxes.scene names its meshes relative to its own folder ("mesh cube.obj").
      const boxes = fs.readFileSync(path.join(h.sourceDir, 'models', 'boxes.scene'), 'utf8');
      const threePixels = await allPixels();
      await andFrame(() => page.selectOption('#scene-start', 'boxes.scene'));
      assert(await editorText() === boxes, 'the editor does not hold models/boxes.scene');
      assert(await page.$eval('#scene-line-error', (e) => e.hidden), 'boxes.scene shows an error');
      assert(await allPixels() !== threePixels, 'the picture did not change to the boxes');
    });

    await check('the download gives the editor\'s text as a .scene file', async () => {
      const [download] = await Promise.all([page.waitForEvent('download'), page.click('#scene-download')]);
      assert(download.suggestedFilename().endsWith('.scene'), `file name ${download.suggestedFilename()}`);
      const saved = fs.readFileSync(await download.path(), 'utf8');
      assert(saved === await editorText(), 'the downloaded text differs from the editor\'s');
    });

    await page.fill('#scene-text', exerciseText);
    await idle();
    await page.waitForTimeout(600);
    await idle();
    await page.$eval('#scene-text', (t) => { t.scrollTop = 0; t.dispatchEvent(new Event('scroll')); });
    await page.evaluate(() => window.scrollTo(0, 0));
    await page.screenshot({ path: path.join(h.screenshotDir, 'viewer-editor.png'), fullPage: true });
  } finally {
    await browser.close();
  }
};
