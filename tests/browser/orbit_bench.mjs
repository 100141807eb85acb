// The viewer's speed as a person sees it (docs/viewer.md): orbits the bunny in headless Chromium by
// dragging on the picture, and measures the frames per second the page shows while the mouse moves
// (request, render, PNG, JSON, decode and draw, all in the loop) and the latency from the last mouse
// move to the frame of the final camera. A benchmark, not a test: it prints figures and asserts
// nothing about them.
//   node orbit_bench.mjs HSR_BINARY MODEL [SIZE] [RUNS]    (defaults: 512, 5)
// Needs playwright-core (npm ci in this folder) and Debian's chromium.

import { spawn } from 'node:child_process';
import path from 'node:path';
import readline from 'node:readline';
import { chromium } from 'playwright-core';

const [hsr, model, sizeArg = '512', runsArg = '5'] = process.argv.slice(2);
if (!hsr || !model) {
  console.error('usage: node orbit_bench.mjs HSR_BINARY MODEL [SIZE] [RUNS]');
  process.exit(2);
}
const size = Number(sizeArg);
const runs = Number(runsArg);
const DRAG_MS = 4000;     // how long each drag lasts
const MOVE_EVERY_MS = 16; // a mouse move per display frame at 60 Hz
const MOVE_PX = 2;        // 2 CSS pixels a move: a slow, steady turn

function startServer() {
  return new Promise((resolve, reject) => {
    const server = spawn(hsr, ['view', '--listen', '127.0.0.1:0', model], { stdio: ['ignore', 'pipe', 'inherit'] });
    server.on('exit', (code) => reject(new Error(`hsr view exited with ${code}`)));
    readline.createInterface({ input: server.stdout }).once('line', (line) => {
      const match = line.match(/http:\/\/127\.0\.0\.1:\d+\/\?token=[0-9a-f]+$/);
      if (match) resolve({ server, url: match[0] });
      else reject(new Error(`unexpected first line from hsr view: ${line}`));
    });
  });
}

const median = (values) => {
  const sorted = [...values].sort((a, b) => a - b);
  const mid = sorted.length >> 1;
  return sorted.length % 2 ? sorted[mid] : (sorted[mid - 1] + sorted[mid]) / 2;
};

const log = (m) => process.stderr.write(`[${(performance.now() / 1000).toFixed(1)} s] ${m}\n`);
const { server, url } = await startServer();
log(`server ${url}`);
let browser = null;
try {
  browser = await chromium.launch({
    executablePath: '/usr/bin/chromium',
    args: ['--headless', '--no-sandbox', '--disable-gpu', '--disable-quic', '--no-first-run',
      '--disable-background-networking', '--disable-component-update', '--disable-sync'],
  });
  const page = await browser.newPage({ viewport: { width: 1400, height: 1000 } });
  await page.goto(url);
  const frame = () => page.$eval('#canvas', (c) => Number(c.dataset.frame || 0));
  const settled = () => page.waitForFunction(() => window.hsrView && window.hsrView.idle()
    && document.querySelector('#canvas').dataset.state === 'ready', null, { timeout: 30_000 });
  await page.waitForFunction(() => Number(document.querySelector('#canvas').dataset.frame || 0) > 0, null, { timeout: 30_000 });
  await page.selectOption('#algorithm', 'zbuffer');
  await page.selectOption('#lighting', 'blinn-phong');
  for (const id of ['#width', '#height']) {
    await page.fill(id, String(size));
    await page.press(id, 'Enter');
  }
  await settled();
  log('page ready');

  const box = await page.$eval('#canvas', (c) => {
    const r = c.getBoundingClientRect();
    return { x: r.left + r.width / 2, y: r.top + r.height / 2, width: r.width };
  });
  const fps = [];
  const latency = [];
  for (let run = 0; run < runs; ++run) {
    await settled();
    // Each drag goes right then, next run, left, so the bunny stays in view.
    const direction = run % 2 ? -1 : 1;
    let x = box.x - (direction * box.width) / 4;
    await page.mouse.move(x, box.y);
    await page.mouse.down();
    const firstFrame = await frame();
    const start = performance.now();
    while (performance.now() - start < DRAG_MS) {
      x += direction * MOVE_PX;
      await page.mouse.move(x, box.y);
      await new Promise((r) => setTimeout(r, MOVE_EVERY_MS));
    }
    const dragEnd = performance.now();
    const framesDuringDrag = (await frame()) - firstFrame;
    await page.mouse.up();
    log(`drag ${run + 1} ended`);
    // The last move is done: wait until the frame shown is the one asked for with the final camera.
    await page.waitForFunction(() => {
      const v = window.hsrView;
      return v && v.idle() && v.lastRequest && v.lastRequest.camera.yaw === v.camera().yaw;
    }, null, { timeout: 30_000, polling: 'raf' });
    const final = performance.now();
    log(`drag ${run + 1}: ${framesDuringDrag} frames`);
    fps.push((framesDuringDrag * 1000) / (dragEnd - start));
    latency.push(final - dragEnd);
  }
  const round = (v) => Math.round(v * 10) / 10;
  console.log(`model ${path.basename(model)}, ${size}x${size}, zbuffer + blinn-phong, ${runs} drags of ${DRAG_MS / 1000} s`);
  console.log(`frames per second while dragging: median ${round(median(fps))} (runs: ${fps.map(round).join(', ')})`);
  console.log(`last mouse move to final frame, ms: median ${round(median(latency))} (runs: ${latency.map(round).join(', ')})`);
} finally {
  await browser?.close();
  server.kill('SIGTERM');
}
