// The theory pane (host/view/web/theory.js): zbuffer's page with no broken figure and no link that
// does not answer, tables as tables, the docs it links to served by the viewer, and the shown step's
// phase marked in the pseudocode and the flowchart, in the page's language. The phases come from the
// test plugin `phased` (tests/plugins/phased.cpp) and its pages (tests/browser/fixtures/), on a
// server of this module's own.

import { spawn } from 'node:child_process';
import fs from 'node:fs';
import path from 'node:path';
import readline from 'node:readline';

function startServer(hsr, pluginDir, scene) {
  return new Promise((resolve, reject) => {
    const server = spawn(hsr, ['view', '--listen', '127.0.0.1:0', '--plugin-path', pluginDir, scene],
      { stdio: ['ignore', 'pipe', 'pipe'] });
    let stderr = '';
    server.stderr.on('data', (d) => { stderr += d; });
    server.on('exit', (code) => reject(new Error(`hsr view exited with ${code}: ${stderr.trim()}`)));
    readline.createInterface({ input: server.stdout }).once('line', (line) => {
      const match = line.match(/(http:\/\/127\.0\.0\.1:\d+\/)\?token=[0-9a-f]+$/);
      if (match) resolve({ server, printed: match[0], base: match[1] });
      else reject(new Error(`unexpected first line from hsr view: ${line}`));
    });
  });
}

// The pane's (or a doc page's) figures that did not load, and its links inside the viewer that do
// not answer 200.
async function brokenParts(page, root) {
  // A figure still on its way is not broken: wait (within bounds) until every one has loaded or failed.
  await page.waitForFunction((r) => [...document.querySelectorAll(`${r} img`)].every((i) => i.complete), root,
    { timeout: 15_000 }).catch(() => {});
  const images = await page.$$eval(`${root} img`, (imgs) => imgs.map((i) => ({ src: i.src, ok: i.complete && i.naturalWidth > 0 })));
  const broken = images.filter((i) => !i.ok).map((i) => `image ${i.src}`);
  const origin = new URL(page.url()).origin;
  const links = await page.$$eval(`${root} a[href]`, (as) => as.map((a) => a.href));
  for (const href of new Set(links)) {
    const url = new URL(href);
    if (url.origin !== origin) continue;
    url.hash = '';
    const status = await page.evaluate(async (u) => (await fetch(u)).status, url.href);
    if (status !== 200) broken.push(`link ${href}: ${status}`);
  }
  return { broken, images: images.length, links: links.length };
}

export default async function theoryChecks(h) {
  const { page, check, assert } = h;

  // zbuffer's page, and every theory page there is (docs/theory/en), as the pane shows them.
  const written = fs.existsSync(path.join(h.sourceDir, 'docs', 'theory', 'en'))
    ? fs.readdirSync(path.join(h.sourceDir, 'docs', 'theory', 'en')).filter((f) => f.endsWith('.md')).map((f) => f.slice(0, -3)) : [];
  const offered = await page.$$eval('#algorithm option', (os) => os.map((o) => o.value));
  const names = [...new Set(['zbuffer', ...written])].filter((n) => offered.includes(n));
  await check(`theory: the pane's pages (${names.join(', ')}): no broken figure or link, tables as tables`, async () => {
    const before = await page.$eval('#algorithm', (s) => s.value);
    await page.click('#theory-toggle');
    try {
      for (const name of names) {
        // The pane's page, whatever the frame of that algorithm does on this scene.
        await page.selectOption('#algorithm', name);
        await page.waitForFunction((n) => document.querySelector('#theory')?.dataset.page === n
          && document.querySelector('#theory h1'), name, { timeout: 20_000 })
          .catch(() => { throw new Error(`${name}: the pane shows no page`); });
        const source = path.join(h.sourceDir, 'docs', 'theory', 'en', `${name}.md`);
        const title = fs.existsSync(source) ? fs.readFileSync(source, 'utf8').split('\n')[0].replace(/^# /, '').replaceAll('`', '') : name;
        assert((await h.text('#theory h1')).startsWith(title), `${name}: heading ${await h.text('#theory h1')}, the page's is ${title}`);
        const { broken, links } = await brokenParts(page, '#theory');
        assert(broken.length === 0, `${name}: ${broken.join('; ')}`);
        assert(links > 0, `${name}: the page links nowhere (the implementation notes at least)`);
        const pipes = await page.$$eval('#theory p', (ps) => ps.filter((p) => /^\s*\|.*\|\s*$/m.test(p.textContent)).length);
        assert(pipes === 0, `${name}: ${pipes} paragraphs are tables shown as text`);
        if (written.includes(name)) {
          assert(await page.$$eval('#theory ol.pseudocode li', (l) => l.length) > 0, `${name}: no pseudocode`);
          assert(await page.$$eval('#theory svg.flowchart g.flow-node', (g) => g.length) > 2, `${name}: no flowchart`);
        }
      }
    } finally {
      await page.click('#theory-toggle');
      await h.idle();
      if (await page.$eval('#algorithm', (s) => s.value) !== before) await h.andFrame(() => page.selectOption('#algorithm', before));
    }
  });

  await check('theory: the docs a page links to are served, their figures and links whole', async () => {
    const own = await h.newBrowser();
    try {
      const doc = own.page;
      const response = await doc.goto(new URL('/docs/algorithms/zbuffer.md', h.serverUrl).href);
      assert(response.status() === 200, `GET /docs/algorithms/zbuffer.md: ${response.status()}`);
      await doc.waitForLoadState('load');
      const { broken, images } = await brokenParts(doc, 'main');
      assert(broken.length === 0, broken.join('; '));
      assert(images > 0, 'zbuffer.md shows no figure');
      assert(await doc.$$eval('main table', (t) => t.length) > 0, 'zbuffer.md\'s tables are not tables');
      for (const bad of ['/docs/../README.md', '/docs/%2e%2e/README.md', '/docs/algorithms/..%2f..%2fREADME.md', '/docs/nothing.md']) {
        const status = await doc.evaluate(async (u) => (await fetch(u)).status, new URL(bad, h.serverUrl).href);
        assert(status === 404 || status === 400, `${bad}: ${status}`);
      }
    } finally {
      await own.browser.close();
    }
  });

  const pluginDir = path.join(path.dirname(h.hsr), 'tests', 'phased-plugin');
  const { server, printed } = await startServer(h.hsr, pluginDir, h.scene);
  const own = await h.newBrowser();
  const p = own.page;
  const frame = () => p.$eval('#canvas', (c) => Number(c.dataset.frame));
  const shown = async (action) => {
    const before = await frame();
    await action();
    await p.waitForFunction((n) => window.hsrView?.idle() && Number(document.querySelector('#canvas').dataset.frame) > n
      && document.querySelector('#canvas').dataset.state !== 'loading', before, { timeout: 20_000 });
  };
  const marked = () => p.$$eval('#theory .current-phase', (els) => els.map((e) => `${e.tagName.toLowerCase()}:${e.dataset.phase}`).sort());
  try {
    await p.goto(printed);
    await p.waitForFunction(() => window.hsrView?.idle() && Number(document.querySelector('#canvas').dataset.frame) > 0, null, { timeout: 20_000 });

    await check('theory: the shown step\'s phase is marked in the pseudocode and the flowchart', async () => {
      await shown(() => p.selectOption('#algorithm', 'phased'));
      if (await p.$eval('#theory', (t) => t.hidden)) await p.click('#theory-toggle');
      await p.waitForSelector('#theory .pseudocode li', { timeout: 20_000 });
      assert(await p.$$eval('#theory table', (t) => t.length) === 1, 'the table is not a table');
      assert(await p.$$eval('#theory svg.flowchart g.decision', (g) => g.length) === 1, 'no diamond for the if');
      assert((await marked()).length === 0, `marked on the full render: ${await marked()}`);
      await shown(() => p.click('#step-forward'));
      assert(JSON.stringify(await marked()) === JSON.stringify(['g:visit', 'li:visit']), `step 1 marks ${await marked()}`);
      await shown(() => p.click('#step-forward'));
      assert(JSON.stringify(await marked()) === JSON.stringify(['g:write', 'li:write']), `step 2 marks ${await marked()}`);
      // The marked line is in view inside the pane, and the page itself has not scrolled.
      const inView = await p.$eval('#theory', (pane) => {
        const line = pane.querySelector('li.current-phase').getBoundingClientRect();
        const box = pane.getBoundingClientRect();
        return line.top >= box.top - 1 && line.bottom <= box.bottom + 1;
      });
      assert(inView, 'the marked line is outside the pane');
      assert(await p.evaluate(() => window.scrollY) === 0, 'the page scrolled');
      await shown(() => p.click('#step-back'));
      assert(JSON.stringify(await marked()) === JSON.stringify(['g:visit', 'li:visit']), `back to step 1 marks ${await marked()}`);
    });

    await check('theory: the pane follows the page\'s language', async () => {
      await p.evaluate(async () => (await import('/static/i18n.js')).setLanguage('ru'));
      await p.waitForFunction(() => document.querySelector('#theory h1')?.textContent.includes('тестовый'), null, { timeout: 20_000 });
      assert(await p.$eval('#theory .pseudocode', (ol) => ol.textContent.includes('для')), 'the pseudocode is not the Russian one');
      assert(JSON.stringify(await marked()) === JSON.stringify(['g:visit', 'li:visit']), `in Russian step 1 marks ${await marked()}`);
      await p.evaluate(async () => (await import('/static/i18n.js')).setLanguage('en'));
      await p.waitForFunction(() => document.querySelector('#theory h1')?.textContent.includes('test plugin'), null, { timeout: 20_000 });
    });
  } finally {
    await own.browser.close();
    server.kill();
  }
}
