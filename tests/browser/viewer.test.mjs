// The hsr view page in a real browser (Debian's chromium, driven by playwright-core): starts
// `hsr view models/boxes.scene`, uses the page as a student would and checks what it shows against
// independent answers: the CLI's own picture for the same camera, the server's face buffer, the
// algorithm's theory page. Saves screenshots of the main views.
//   node viewer.test.mjs HSR_BINARY SOURCE_DIR [SCREENSHOT_DIR]   (default: SOURCE_DIR/docs/images)
// Ends with "N passed, N failed"; exits 1 if anything failed, 77 (skip) without chromium.

import { spawn, execFileSync } from 'node:child_process';
import fs from 'node:fs';
import os from 'node:os';
import path from 'node:path';
import readline from 'node:readline';
import { chromium } from 'playwright-core';

const [hsr, sourceDir, screenshotArg] = process.argv.slice(2);
if (!hsr || !sourceDir) {
  console.error('usage: node viewer.test.mjs HSR_BINARY SOURCE_DIR [SCREENSHOT_DIR]');
  process.exit(2);
}
const CHROMIUM = '/usr/bin/chromium';
if (!fs.existsSync(CHROMIUM)) {
  console.log(`skipped: ${CHROMIUM} is not installed (apt-get install chromium)`);
  process.exit(77);
}
const screenshotDir = screenshotArg || path.join(sourceDir, 'docs', 'images');
fs.mkdirSync(screenshotDir, { recursive: true });
const scratch = fs.mkdtempSync(path.join(os.tmpdir(), 'hsr-viewer-test-'));
const scene = path.join(sourceDir, 'models', 'boxes.scene');

// The whole test is bounded: whatever hangs, it ends within five minutes.
const deadline = setTimeout(() => {
  console.error('FAIL: the test took over 300 s');
  finish(1);
}, 300_000);

let server = null;
let browser = null;
let passed = 0;
let failed = 0;

async function finish(code) {
  clearTimeout(deadline);
  try { await browser?.close(); } catch { /* already gone */ }
  if (server && server.exitCode === null) server.kill('SIGTERM');
  fs.rmSync(scratch, { recursive: true, force: true });
  console.log(`${passed} passed, ${failed} failed`);
  process.exit(code);
}

async function check(name, fn) {
  const started = Date.now();
  try {
    await fn();
    passed += 1;
    console.log(`ok    ${name} (${Date.now() - started} ms)`);
  } catch (e) {
    failed += 1;
    console.log(`FAIL  ${name}: ${e.message.split('\n').slice(0, 6).join('\n      ')}`);
  }
}

function assert(condition, message) {
  if (!condition) throw new Error(message);
}

// ---- the server ---------------------------------------------------------------------------------

function startServer() {
  return new Promise((resolve, reject) => {
    // The test plugins that misbehave on request (tests/plugins/misbehaving.cpp), as a third party's.
    const misbehaving = path.join(path.dirname(hsr), 'tests', 'misbehaving-plugins');
    server = spawn(hsr, ['view', '--listen', '127.0.0.1:0', '--plugin-path', misbehaving, scene],
      { stdio: ['ignore', 'pipe', 'pipe'] });
    let stderr = '';
    server.stderr.on('data', (d) => { stderr += d; });
    server.on('exit', (code) => reject(new Error(`hsr view exited with ${code}: ${stderr.trim()}`)));
    const lines = readline.createInterface({ input: server.stdout });
    // The printed URL carries the token: opening it sets the page's cookie.
    lines.once('line', (line) => {
      const match = line.match(/(http:\/\/127\.0\.0\.1:\d+\/)\?token=([0-9a-f]+)$/);
      if (match) resolve({ printed: match[0], base: match[1], token: match[2] });
      else reject(new Error(`unexpected first line from hsr view: ${line}`));
    });
  });
}

// ---- the page -----------------------------------------------------------------------------------

let page;
const pageErrors = [];

// Waits until a frame newer than `after` is shown (or failed) and nothing more is on its way.
async function settled(after) {
  await page.waitForFunction((n) => {
    const c = document.querySelector('#canvas');
    return window.hsrView && window.hsrView.idle() && Number(c.dataset.frame) > n && c.dataset.state !== 'loading';
  }, after, { timeout: 20_000 });
}

const frameNumber = () => page.$eval('#canvas', (c) => Number(c.dataset.frame));
const errorState = () => page.$eval('#canvas', (c) => c.dataset.state === 'error');

// Does `action` and waits for the frame it causes.
async function andFrame(action) {
  const before = await frameNumber();
  await action();
  await settled(before);
}

// Waits for the page to be idle without requiring a new frame (after an error, say).
async function idle() {
  await page.waitForFunction(() => window.hsrView && window.hsrView.idle()
    && document.querySelector('#canvas').dataset.state !== 'loading', null, { timeout: 20_000 });
}

// The canvas's pixels as a string of hex bytes' hash-free stand-in: base64 of the RGBA data.
const canvasPixels = () => page.$eval('#canvas', (c) => {
  const data = c.getContext('2d').getImageData(0, 0, c.width, c.height).data;
  let s = '';
  for (let i = 0; i < data.length; i += 4096) s += String.fromCharCode(...data.subarray(i, i + 4096));
  return btoa(s);
});

const text = (selector) => page.$eval(selector, (e) => e.textContent.trim());

async function screenshot(name) {
  await page.evaluate(() => window.scrollTo(0, 0));
  await page.screenshot({ path: path.join(screenshotDir, `viewer-${name}.png`), fullPage: true });
}

// The centre of image pixel (x, y) in page coordinates.
async function pixelPoint(x, y) {
  const box = await page.$eval('#canvas', (c) => {
    const r = c.getBoundingClientRect();
    return { left: r.left, top: r.top, width: r.width, height: r.height, w: c.width, h: c.height };
  });
  return { x: box.left + ((x + 0.5) * box.width) / box.w, y: box.top + ((y + 0.5) * box.height) / box.h };
}

// Runs the command line the page shows for its picture (#cli), writing to `output`.
function runShownCommand(shown, output) {
  const words = shown.split(/\s+/);
  assert(words[0] === 'hsr' && words[1] === 'render' && words[2] === 'boxes.scene', `#cli: ${shown}`);
  const args = ['render', scene, ...words.slice(3)];
  const o = args.indexOf('-o');
  assert(o > 0, `no -o in #cli: ${shown}`);
  args[o + 1] = output;
  execFileSync(hsr, args, { stdio: ['ignore', 'ignore', 'pipe'] });
  return shown;
}

// ---- the test -----------------------------------------------------------------------------------

let serverUrl;
let printedUrl;
let apiHeaders;  // what this script's own requests carry instead of the page's cookie

async function main() {
  const { printed, base, token } = await startServer();
  printedUrl = printed;
  serverUrl = base;
  apiHeaders = { 'Content-Type': 'application/json', 'X-HSR-Token': token };
  console.log(`server: ${base}`);
  browser = await chromium.launchPersistentContext(path.join(scratch, 'profile'), {
    executablePath: CHROMIUM,
    headless: true,
    viewport: { width: 1400, height: 920 },
    args: ['--headless', '--no-sandbox', '--disable-gpu', '--disable-quic', '--no-first-run',
      '--disable-background-networking', '--disable-component-update', '--disable-sync'],
  });
  page = browser.pages()[0] || await browser.newPage();
  page.setDefaultTimeout(10_000);
  page.on('pageerror', (e) => pageErrors.push(e.message));

  await check('the page loads and shows the scene given on the command line', async () => {
    await page.goto(printed);
    assert(page.url() === serverUrl, `the address bar keeps the token: ${page.url()}`);
    await settled(0);
    assert(!(await errorState()), `first frame failed: ${await text('#error')}`);
    assert((await page.$eval('#model', (s) => s.value)).endsWith('boxes.scene'), 'boxes.scene is not selected');
  });

  await check('without the token, or from another site, the API refuses', async () => {
    const info = await fetch(new URL('api/info', serverUrl));
    assert(info.status === 403, `GET /api/info without the token: ${info.status}`);
    assert(/open the URL hsr view printed/.test((await info.json()).error), 'the refusal does not say what to do');
    const request = await page.evaluate(() => window.hsrView.lastRequest);
    const crossSite = await fetch(new URL('api/frame', serverUrl), {
      method: 'POST', headers: { ...apiHeaders, 'Content-Type': 'text/plain', Origin: 'http://attacker.example' },
      body: JSON.stringify(request) });
    assert(crossSite.status === 403, `a cross-site text/plain POST: ${crossSite.status}`);
    // The page's own requests carry the cookie the printed URL set.
    const own = await page.evaluate(async () => (await fetch('/api/info')).status);
    assert(own === 200, `the page's GET /api/info: ${own}`);
  });

  await check('picking an algorithm and a lighting model renders with them', async () => {
    await andFrame(() => page.selectOption('#algorithm', 'zbuffer'));
    await andFrame(() => page.selectOption('#lighting', 'lambert'));
    const request = await page.evaluate(() => window.hsrView.lastRequest);
    assert(request.algorithm === 'zbuffer' && request.lighting === 'lambert',
      `request has ${request.algorithm} and ${request.lighting}`);
    assert(/rendered in \d+ ms/.test(await text('#status')), `status: ${await text('#status')}`);
    assert((await text('#stats')).includes('triangles'), 'no counters in #stats');
  });

  await check('dragging on the picture orbits the camera', async () => {
    const before = await canvasPixels();
    const yawBefore = (await page.evaluate(() => window.hsrView.lastRequest)).camera.yaw;
    const start = await pixelPoint(256, 256);
    await andFrame(async () => {
      await page.mouse.move(start.x, start.y);
      await page.mouse.down();
      await page.mouse.move(start.x + 60, start.y + 20, { steps: 6 });
      await page.mouse.up();
      await page.mouse.move(5, 5);  // off the picture: no hover readout wanted yet
    });
    await idle();
    const request = await page.evaluate(() => window.hsrView.lastRequest);
    assert(request.camera.yaw !== yawBefore, `yaw stayed ${yawBefore}`);
    assert(await canvasPixels() !== before, 'the picture did not change');
  });
  await screenshot('main');

  await check('changing a parameter renders with it', async () => {
    await andFrame(() => page.check('#params [name="cull-backfaces"]'));
    const request = await page.evaluate(() => window.hsrView.lastRequest);
    assert(request.params['cull-backfaces'] === 'true', `params: ${JSON.stringify(request.params)}`);
    assert(!(await errorState()), await text('#error'));
  });

  await check('the step bar starts at the slowest speed and knows its total before any step', async () => {
    assert(await page.$eval('#step-speed', (s) => s.value) === '1', 'the speed is not 1 step/s');
    await page.waitForFunction(() => /^\/ \d+$/.test(document.querySelector('#step-total').textContent), null,
      { timeout: 20_000 });
    assert(/^the full render \(\d+ steps\)$/.test(await text('#step-text')), `step text: ${await text('#step-text')}`);
    assert(await page.$eval('#step-text', (e) => e.getAttribute('aria-live')) === 'polite',
      'the step text is not a polite live region');
  });

  await check('stepping forward and back changes the step text and the picture', async () => {
    const full = await canvasPixels();
    await andFrame(() => page.click('#step-forward'));
    const text1 = await text('#step-text');
    const picture1 = await canvasPixels();
    await andFrame(() => page.click('#step-forward'));
    const text2 = await text('#step-text');
    await andFrame(() => page.click('#step-back'));
    assert(/^step 1\b/.test(text1), `step text: ${text1}`);
    assert(/^step 2\b/.test(text2), `step text: ${text2}`);
    assert(text1 !== text2, 'the step text did not change');
    assert(picture1 !== full, 'step 1 looks like the full render');
    assert(await text('#step-text') === text1, 'step back did not return to step 1');
    assert(await canvasPixels() === picture1, 'step back did not return to step 1\'s picture');
    const highlighted = await page.$eval('#overlay', (c) => c.getContext('2d').getImageData(0, 0, c.width, c.height)
      .data.some((v, i) => i % 4 === 3 && v > 0));
    assert(highlighted, 'the overlay shows no highlight');
  });

  await check('jumping with the number box shows that step, highlighted', async () => {
    const { request, response } = await page.evaluate(() => ({
      request: window.hsrView.lastRequest, response: window.hsrView.lastResponse }));
    const total = response.steps.total;
    assert(Number.isInteger(total) && total > 2, `total: ${total}`);
    // The step to show: the one whose triangle both writes and is rejected at the most pixels
    // (the most telling picture for the docs), asked of the server directly.
    let k = response.steps.current === 2 ? 3 : 2;
    let most = -1;
    for (let step = 1; step <= Math.min(total, 64); step += 1) {
      if (step === response.steps.current) continue;  // a jump must go somewhere
      const answer = await (await fetch(new URL('api/frame', serverUrl), {
        method: 'POST', headers: apiHeaders, body: JSON.stringify({ ...request, step }) })).json();
      const written = answer.steps?.written?.length ?? 0;
      const rejected = answer.steps?.rejected?.length ?? 0;
      const score = Math.min(written, rejected) * 4 + written + rejected;
      if (score > most) {
        most = score;
        k = step;
      }
    }
    await andFrame(async () => {
      await page.fill('#step-number', String(k));
      await page.press('#step-number', 'Enter');
    });
    assert((await text('#step-text')).startsWith(`step ${k}:`), `step text: ${await text('#step-text')}`);
    assert(await page.$eval('#step-slider', (s) => Number(s.value)) === k, 'the slider did not follow');
  });
  await screenshot('steps');

  await check('the keys step with a select or checkbox focused, and leave them as they are', async () => {
    const stepShown = async () => Number((await text('#step-text')).match(/^step (\d+):/)?.[1]);
    const k = await stepShown();
    const total = Number((await text('#step-total')).slice(2));
    await page.selectOption('#step-speed', '5');
    await page.focus('#step-speed');
    await andFrame(() => page.keyboard.press('ArrowRight'));
    assert(await stepShown() === k + 1, `→ showed ${await text('#step-text')} after step ${k}`);
    await andFrame(() => page.keyboard.press('ArrowLeft'));
    assert(await stepShown() === k, `← showed ${await text('#step-text')} after step ${k + 1}`);
    assert(await page.$eval('#step-speed', (s) => s.value) === '5', 'the arrows changed the speed');
    await andFrame(() => page.keyboard.press('End'));
    assert(await stepShown() === total, `End showed ${await text('#step-text')} of ${total}`);
    await andFrame(() => page.keyboard.press('Home'));
    assert(await stepShown() === 1, `Home showed ${await text('#step-text')}`);
    // Space plays and pauses with a checkbox focused, which keeps its state.
    const box = '#params input[type="checkbox"]';
    const checked = await page.$eval(box, (b) => b.checked);
    await page.focus(box);
    await page.keyboard.press('Space');
    assert(await page.$eval('#step-play', (b) => b.getAttribute('aria-label')) === 'pause', 'space did not play');
    await page.keyboard.press('Space');
    assert(await page.$eval('#step-play', (b) => b.getAttribute('aria-label')) === 'play', 'space did not pause');
    assert(await page.$eval(box, (b) => b.checked) === checked, 'space toggled the checkbox');
    // On the focused play button, space plays once (not also as the button's click).
    await page.focus('#step-play');
    await page.keyboard.press('Space');
    assert(await page.$eval('#step-play', (b) => b.getAttribute('aria-label')) === 'pause', 'space on play did not play');
    await page.keyboard.press('Space');
    assert(await page.$eval('#step-play', (b) => b.getAttribute('aria-label')) === 'play', 'space on play did not pause');
    // In a field that takes typing the keys type: space in the step number box does not play.
    await page.focus('#step-number');
    await page.keyboard.press('Space');
    assert(await page.$eval('#step-play', (b) => b.getAttribute('aria-label')) === 'play', 'space in the number box played');
    await idle();
    await page.selectOption('#step-speed', '1');
  });

  await check('a step the server does not answer stops playing and says so', async () => {
    await page.route('**/api/frame', (route) => route.abort());
    try {
      const number = await page.$eval('#step-number', (n) => n.value);
      await page.locator('#step-play').click();
      await page.waitForFunction(() => /^stepping stopped: /.test(document.querySelector('#step-text').textContent),
        null, { timeout: 20_000 });
      await idle();
      assert(await page.$eval('#step-play', (b) => b.getAttribute('aria-label')) === 'play', 'still playing');
      assert(await page.$eval('#step-number', (n) => n.value) === number, 'the step number counted on');
    } finally {
      await page.unroute('**/api/frame');
    }
  });

  await check('the last step is the CLI\'s picture for the same camera, pixel for pixel', async () => {
    await andFrame(() => page.click('#step-last'));
    const response = await page.evaluate(() => window.hsrView.lastResponse);
    assert(response.steps && response.steps.current === response.steps.total,
      `step ${response.steps?.current} of ${response.steps?.total}`);
    // The page's own command line for its picture, without --step (the last step is the full render).
    const shownCommand = (await text('#cli')).replace(/ --step \d+/, '');
    assert(/--yaw \S+ --pitch \S+ --zoom \S+/.test(shownCommand), `#cli: ${shownCommand}`);
    const output = path.join(scratch, 'cli.png');
    const command = runShownCommand(shownCommand, output);
    const cliPng = fs.readFileSync(output);
    // What the canvas shows equals the CLI's PNG decoded by the browser, every byte of every pixel
    // (the PNG files themselves may differ in their compression).
    const same = await page.evaluate(async (dataUrl) => {
      const image = new Image();
      image.src = dataUrl;
      await image.decode();
      const c = document.createElement('canvas');
      c.width = image.width;
      c.height = image.height;
      c.getContext('2d').drawImage(image, 0, 0);
      const cli = c.getContext('2d').getImageData(0, 0, c.width, c.height).data;
      const shown = document.querySelector('#canvas');
      const own = shown.getContext('2d').getImageData(0, 0, shown.width, shown.height).data;
      return cli.length === own.length && cli.every((v, i) => v === own[i]);
    }, `data:image/png;base64,${cliPng.toString('base64')}`);
    assert(same, `the canvas's pixels differ from ${command}`);
  });

  await check('hovering a pixel shows the face the server\'s face buffer has there', async () => {
    const request = await page.evaluate(() => window.hsrView.lastRequest);
    const answer = await fetch(new URL('api/frame', serverUrl), {
      method: 'POST', headers: apiHeaders, body: JSON.stringify({ ...request, buffers: true }) });
    // The answer with buffers: the JSON's length, the JSON, then the arrays it points into.
    assert(answer.headers.get('content-type') === 'application/vnd.hsr.frame', 'the answer with buffers is not binary');
    const bytes = await answer.arrayBuffer();
    const length = new DataView(bytes).getUint32(0, true);
    const json = JSON.parse(new TextDecoder().decode(new Uint8Array(bytes, 4, length)));
    const base = Math.ceil((4 + length) / 4) * 4;
    const face = { width: json.width, height: json.height,
      ids: new Uint32Array(bytes, base + json.buffers.face.offset, json.buffers.face.length) };
    // The covered pixel nearest the centre.
    let best = null;
    for (let y = 0; y < face.height; y += 1) {
      for (let x = 0; x < face.width; x += 1) {
        const id = face.ids[y * face.width + x];
        const d = (x - face.width / 2) ** 2 + (y - face.height / 2) ** 2;
        if (id !== 4294967295 && (!best || d < best.d)) best = { x, y, id, d };
      }
    }
    assert(best, 'the server\'s face buffer is empty');
    const point = await pixelPoint(best.x, best.y);
    await page.mouse.move(point.x, point.y);
    const prefix = `${best.x}, ${best.y}: depth `;
    await page.waitForFunction((p) => document.querySelector('#pixel-info').textContent.startsWith(p), prefix,
      { timeout: 20_000 });
    const info = await text('#pixel-info');
    const shownFace = Number((info.match(/face (\d+)/) || [])[1]);
    assert(shownFace === best.id, `#pixel-info says "${info}", the face buffer has ${best.id}`);
    assert(/object (\d+|none), instance (\d+|none)/.test(info), `no object and instance in "${info}"`);
  });

  await check('the depth buffer view shows a false-colour picture and its range', async () => {
    await page.selectOption('#buffer-select', 'depth');
    await page.waitForSelector('#legend:not([hidden])', { timeout: 20_000 });
    const low = Number(await text('#legend-min'));
    const high = Number(await text('#legend-max'));
    assert(low >= 0 && low < high && high <= 1, `legend ${low} .. ${high}`);
  });
  await screenshot('buffers');
  await page.selectOption('#buffer-select', 'frame');
  await page.mouse.move(5, 5);

  await check('the theory pane shows the algorithm\'s page', async () => {
    // docs/theory/en/zbuffer.md, or the page made from the plugin's description while there is none
    const page_ = path.join(sourceDir, 'docs', 'theory', 'en', 'zbuffer.md');
    const heading = fs.existsSync(page_)
      ? fs.readFileSync(page_, 'utf8').split('\n')[0].replace(/^#\s+/, '').replace(/`/g, '') : 'zbuffer';
    await page.click('#theory-toggle');
    await page.waitForSelector('#theory:not([hidden]) h1', { timeout: 20_000 });
    assert(await text('#theory h1') === heading, `theory heading: ${await text('#theory h1')}, expected ${heading}`);
  });
  await screenshot('theory');
  await page.click('#theory-toggle');

  await check('compare shows a second algorithm on the same camera with the differing pixels', async () => {
    await andFrame(async () => {
      await page.selectOption('#compare-algorithm', 'scanline-zbuffer');
      await page.check('#compare-toggle');
    });
    assert(!(await errorState()), await text('#error'));
    const count = Number((await text('#compare-diff')).replace(/,/g, ''));
    assert(Number.isInteger(count) && count >= 0, `#compare-diff: ${await text('#compare-diff')}`);
    assert((await text('#compare-stats')).includes('scanline-zbuffer'), 'no stats of the compared algorithm');
    await page.waitForFunction(() => document.querySelector('#compare-diff-image').complete
      && document.querySelector('#compare-diff-image').naturalWidth > 0);
  });
  await screenshot('compare');
  await andFrame(() => page.uncheck('#compare-toggle'));

  await check('a bad parameter shows the server\'s message next to its field', async () => {
    await andFrame(() => page.selectOption('#algorithm', 'hierarchical-zbuffer'));
    await page.fill('#params [name="tile-size"]', '1000');
    await page.press('#params [name="tile-size"]', 'Tab');
    await page.waitForFunction(() => document.querySelector('#params .field[data-name="tile-size"] .field-error')
      ?.textContent.trim().length > 0, null, { timeout: 20_000 });
    const message = await text('#params .field[data-name="tile-size"] .field-error');
    assert(/tile-size/.test(message), `message: ${message}`);
    const info = await page.evaluate(async () => (await fetch('/api/info')).json());
    assert(typeof info.version === 'string', 'the server did not answer /api/info after the error');
    await andFrame(async () => {
      await page.fill('#params [name="tile-size"]', '16');
      await page.press('#params [name="tile-size"]', 'Tab');
    });
    assert(!(await errorState()), `still failing: ${await text('#error')}`);
    assert(await text('#params .field[data-name="tile-size"] .field-error') === '', 'the message stayed');
  });

  await check('settings are kept between visits', async () => {
    await page.reload();
    await settled(0);
    const kept = await page.evaluate(() => ({
      algorithm: document.querySelector('#algorithm').value, lighting: document.querySelector('#lighting').value,
      tile: document.querySelector('#params [name="tile-size"]').value, request: window.hsrView.lastRequest }));
    assert(kept.algorithm === 'hierarchical-zbuffer' && kept.lighting === 'lambert' && kept.tile === '16',
      `after reload: ${JSON.stringify({ ...kept, request: undefined })}`);
    assert(kept.request.camera.yaw !== 30, 'the camera was not kept');
  });

  await check('hierarchical-zbuffer\'s steps offer its z-pyramid levels as buffers to show', async () => {
    await andFrame(() => page.click('#step-forward'));
    const options = await page.$$eval('#buffer-select option', (all) => all.map((o) => o.value));
    const levels = options.filter((v) => /^step:z-pyramid-\d+$/.test(v));
    assert(levels.length > 0, `buffer options: ${options.join(', ')}`);
    const before = await canvasPixels();
    await page.selectOption('#buffer-select', levels[0]);
    await idle();
    assert(await canvasPixels() !== before, `showing ${levels[0]} left the picture as it was`);
    assert(!(await errorState()), await text('#error'));
    await screenshot('pyramid');
    await page.selectOption('#buffer-select', 'frame');
    await andFrame(() => page.click('#step-last'));
  });

  await check('a small picture shows the pixel grid with each pixel\'s depth', async () => {
    await andFrame(async () => {
      await page.fill('#width', '16');
      await page.press('#width', 'Tab');
    });
    await andFrame(async () => {
      await page.fill('#height', '12');
      await page.press('#height', 'Tab');
    });
    await page.waitForSelector('#grid:not([hidden]) .cell', { timeout: 20_000 });
    await idle();
    const cells = await page.$$eval('#grid .cell', (all) => all.map((c) => c.textContent));
    assert(cells.length === 16 * 12, `${cells.length} cells`);
    assert(cells.every((c) => c === '∞' || /^\d*\.?\d+(e-?\d+)?$/.test(c)), `not a depth: ${cells.find((c) => c.includes(','))}`);
    assert(cells.some((c) => c !== '∞'), 'no depth in any cell');
    await screenshot('grid');
    await page.fill('#width', '512');
    await page.press('#width', 'Tab');
    await page.fill('#height', '512');
    await page.press('#height', 'Tab');
    await idle();
  });

  await check('a frame that takes long counts its seconds, and Stop stops it', async () => {
    await andFrame(() => page.selectOption('#algorithm', 'misbehaving'));
    // The plugin loops forever in render: the server stops it when the page asks.
    await page.selectOption('#params [name="fault"]', 'loop');
    await page.waitForSelector('#stop:not([hidden])', { timeout: 20_000 });
    assert(/rendering… \d+ s/.test(await text('#status')), `status: ${await text('#status')}`);
    await page.click('#stop');
    await page.waitForFunction(() => document.querySelector('#status').textContent === 'stopped', null,
      { timeout: 20_000 });
    await idle();
    assert(await page.$eval('#stop', (b) => b.hidden), 'Stop is still shown');
    // The worker that looped was replaced: the next frame renders.
    await andFrame(() => page.selectOption('#params [name="fault"]', 'none'));
    assert(!(await errorState()), await text('#error'));
    await andFrame(() => page.selectOption('#algorithm', 'zbuffer'));
  });

  await check('a plugin that crashes answers with its name, and the next frame renders', async () => {
    await andFrame(() => page.selectOption('#algorithm', 'misbehaving'));
    await page.selectOption('#params [name="fault"]', 'segfault');
    await page.waitForFunction(() => document.querySelector('#canvas').dataset.state === 'error', null,
      { timeout: 20_000 });
    assert(/plugin 'misbehaving' crashed in render \(SIGSEGV\)/.test(await text('#error')), `error: ${await text('#error')}`);
    await andFrame(() => page.selectOption('#params [name="fault"]', 'none'));
    assert(!(await errorState()), await text('#error'));
    await andFrame(() => page.selectOption('#algorithm', 'zbuffer'));
  });

  await check('the picture fills the window: larger on a large one, near the top of a small one', async () => {
    const box = () => page.$eval('#canvas', (c) => {
      window.scrollTo(0, 0);
      const r = c.getBoundingClientRect();
      return { width: r.width, top: r.top, bottom: r.bottom };
    });
    await page.setViewportSize({ width: 1280, height: 800 });
    const medium = await box();
    await page.setViewportSize({ width: 1920, height: 1080 });
    const large = await box();
    await page.setViewportSize({ width: 800, height: 600 });
    const small = await box();
    await page.setViewportSize({ width: 1400, height: 920 });
    assert(large.width > medium.width * 1.2, `${large.width} px wide at 1920×1080, ${medium.width} px at 1280×800`);
    assert(large.width > 600, `${large.width} px wide at 1920×1080`);
    assert(small.top < 150 && small.bottom <= 600, `at 800×600 the picture spans ${small.top}–${small.bottom} px`);
  });

  // The checks of the other *.checks.mjs files beside this one, each a module whose default export
  // takes this harness. Each leaves the main page as it found it, or works in pages of its own.
  const harness = {
    hsr, sourceDir, scratch, scene, screenshotDir, serverUrl, printedUrl, apiHeaders, browser, page, pageErrors,
    check, assert, settled, andFrame, idle, frameNumber, errorState, canvasPixels, text, screenshot, pixelPoint,
    // The value of `page`'s model option for the shipped model `name` (not an upload), once the list
    // holds it (the list is filled from the server, later on a loaded machine); undefined after 30 s.
    async modelOption(onPage, name) {
      const find = (n) => [...document.querySelector('#model').options].map((o) => o.value)
        .find((v) => !v.startsWith('upload/') && v.endsWith(`/${n}`));
      await onPage.waitForFunction(find, name, { timeout: 30_000 }).catch(() => {});
      return onPage.evaluate(find, name);
    },
    // A page of its own in a browser of its own (for a locale or a touch screen), its errors collected
    // in pageErrors; the caller closes the browser.
    async newBrowser(options = {}) {
      const own = await chromium.launch({
        executablePath: CHROMIUM, headless: true,
        args: ['--headless', '--no-sandbox', '--disable-gpu', '--disable-quic', '--no-first-run',
          '--disable-background-networking', '--disable-component-update', '--disable-sync'],
      });
      const context = await own.newContext({ viewport: { width: 1400, height: 920 }, ...options });
      const ownPage = await context.newPage();
      ownPage.setDefaultTimeout(10_000);
      ownPage.on('pageerror', (e) => pageErrors.push(e.message));
      await ownPage.goto(printedUrl);
      return { browser: own, page: ownPage };
    },
  };
  const here = path.dirname(new URL(import.meta.url).pathname);
  for (const file of fs.readdirSync(here).filter((f) => f.endsWith('.checks.mjs')).sort()) {
    const checks = await import(path.join(here, file));
    await checks.default(harness);
  }

  await check('the page raised no script errors', async () => {
    assert(pageErrors.length === 0, pageErrors.join('; '));
  });
}

try {
  await main();
} catch (e) {
  failed += 1;
  console.log(`FAIL  ${e.message}`);
}
await finish(failed ? 1 : 0);
