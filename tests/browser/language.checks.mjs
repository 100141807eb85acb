// The page's two languages and the presentation view, in a browser of its own whose locale is
// Russian (viewer.test.mjs runs this module with its harness h). Checks that the page comes up in
// Russian, that a step's text comes from the server in Russian, that EN switches every word and the
// step text and that the choice survives a reload; and that the presentation view shows the picture
// and the step text larger at 1920×1080. Screenshot: viewer-russian.png (the z-buffer's full render).
//
// The step texts are those the host writes for a plugin that writes none (handmade-steps, of the
// test plugins: tests/plugins/handmade.c), so this page talks to a server of its own that loads the
// test plugins beside the built-in ones.

import { spawn } from 'node:child_process';
import fs from 'node:fs';
import path from 'node:path';
import readline from 'node:readline';

// `hsr view` of the harness's scene with the test plugins; resolves to {server, url}.
function startServer(h) {
  const plugins = path.join(path.dirname(h.hsr), 'tests', 'plugins');
  if (!fs.existsSync(path.join(plugins, 'handmade-steps.so'))) {
    return Promise.reject(new Error(`${plugins}/handmade-steps.so is not built (cmake --build build --target hsr_test_plugins)`));
  }
  return new Promise((resolve, reject) => {
    const server = spawn(h.hsr, ['view', '--listen', '127.0.0.1:0', '--plugin-path', plugins, h.scene],
      { stdio: ['ignore', 'pipe', 'pipe'] });
    server.stderr.resume();
    server.on('exit', (code) => reject(new Error(`hsr view exited with ${code}`)));
    readline.createInterface({ input: server.stdout }).once('line', (line) => {
      const match = line.match(/http:\/\/127\.0\.0\.1:\d+\/\?token=[0-9a-f]+$/);
      if (match) resolve({ server, url: match[0] });
      else reject(new Error(`unexpected first line from hsr view: ${line}`));
    });
  });
}

const CYRILLIC = /[\u0400-\u04FF]/;

export default async (h) => {
  const { check, assert } = h;
  let own = null;
  let page = null;
  let server = null;

  const frameNumber = () => page.$eval('#canvas', (c) => Number(c.dataset.frame));
  const settled = (after) => page.waitForFunction((n) => {
    const c = document.querySelector('#canvas');
    return window.hsrView && window.hsrView.idle() && Number(c.dataset.frame) > n && c.dataset.state !== 'loading';
  }, after, { timeout: 20_000 });
  const andFrame = async (action) => {
    const before = await frameNumber();
    await action();
    await settled(before);
  };
  const text = (selector) => page.$eval(selector, (e) => e.textContent.trim());
  const headings = () => page.$$eval('.panel h2', (list) => list.map((e) => e.textContent.trim()));
  const stepText = () => text('#step-text');
  const lastStep = () => page.evaluate(() => ({
    language: window.hsrView.lastRequest?.language, step: window.hsrView.lastRequest?.step,
    text: window.hsrView.lastResponse?.steps?.text,
  }));
  const fullRenderShown = (pattern) => page.waitForFunction((source) => new RegExp(source).test(
    document.querySelector('#step-text').textContent.trim()), pattern.source, { timeout: 20_000 });

  try {
    await check('language: a browser that prefers Russian gets the page in Russian', async () => {
      const started = await startServer(h);
      server = started.server;
      own = await h.newBrowser({ locale: 'ru-RU' });
      page = own.page;
      await page.goto(started.url);
      await settled(0);
      assert(await page.evaluate(() => navigator.languages[0]) === 'ru-RU', 'the browser does not prefer Russian');
      assert(await page.$eval('html', (e) => e.lang) === 'ru', 'html lang is not ru');
      const shown = await headings();
      for (const word of ['Модель', 'Алгоритм', 'Освещение', 'Камера', 'Сравнить', 'Статистика']) {
        assert(shown.includes(word), `the panels are headed ${shown.join(', ')}`);
      }
      assert(await text('#theory-toggle') === 'Теория', `theory button: ${await text('#theory-toggle')}`);
      assert(/^отрисовано за \d+ мс$/.test(await text('#status')), `status: ${await text('#status')}`);
      assert(await page.$eval('#step-first', (e) => e.getAttribute('aria-label')) === 'первый шаг', 'first step button');
      assert(await page.$eval('#step-number', (e) => e.placeholder) === 'все', 'step number placeholder');
      assert((await text('label[data-i18n="speed"]')).startsWith('скорость'), 'speed label');
      assert(await page.$eval('#step-speed', (s) => s.options[0].text) === '1 шаг/с', 'speed option');
      await fullRenderShown(/^полное изображение \(шагов: \d+\)$/);
      assert(await page.$eval('[data-language="ru"]', (e) => e.getAttribute('aria-pressed')) === 'true', 'RU not pressed');
      const stored = await page.evaluate(() => JSON.parse(localStorage.getItem('hsr-view-settings')).language);
      assert(stored === null, `the language was stored as ${stored} before anyone chose one`);
      await page.evaluate(() => window.scrollTo(0, 0));
      await page.screenshot({ path: path.join(h.screenshotDir, 'viewer-russian.png'), fullPage: true });
    });

    await check('language: a step\'s text comes in Russian', async () => {
      assert(page, 'no page');
      await andFrame(() => page.selectOption('#algorithm', 'handmade-steps'));
      assert(await page.$eval('#algorithm', (s) => s.selectedOptions[0].text) === 'handmade-steps (по шагам)',
        'the algorithm list does not mark the plugins that step in Russian');
      await andFrame(() => page.click('#step-forward'));
      const step = await lastStep();
      assert(step.step === 1 && step.language === 'ru', `asked for ${JSON.stringify(step)}`);
      // handmade-steps fills row 0 of the picture, every pixel of it, in step 1.
      const width = await page.$eval('#canvas', (c) => c.width);
      const expected = `шаг 1 (row): треугольник 0; записано пикселей: ${width}, отброшено: 0`;
      assert(step.text === expected, `step 1's text from the server: ${step.text}`);
      assert(await stepText() === `шаг 1: ${expected}`, `step text: ${await stepText()}`);
    });

    await check('language: EN switches the words and asks for the step again in English', async () => {
      assert(page, 'no page');
      await andFrame(() => page.click('[data-language="en"]'));
      assert(await page.$eval('html', (e) => e.lang) === 'en', 'html lang is not en');
      const shown = await headings();
      for (const word of ['Model', 'Algorithm', 'Camera', 'Compare']) assert(shown.includes(word), `headings: ${shown}`);
      assert(await text('#theory-toggle') === 'Theory', `theory button: ${await text('#theory-toggle')}`);
      assert(await page.$eval('#step-first', (e) => e.getAttribute('aria-label')) === 'first step', 'first step button');
      const step = await lastStep();
      assert(step.step === 1 && step.language === 'en', `asked for ${JSON.stringify(step)}`);
      const width = await page.$eval('#canvas', (c) => c.width);
      assert(step.text === `row 1: triangle 0, ${width} pixels written, 0 rejected`, `step 1's text in English: ${step.text}`);
      assert((await stepText()).startsWith('step 1: ') && !CYRILLIC.test(await stepText()), `step text: ${await stepText()}`);
      assert(/^rendered in \d+ ms$/.test(await text('#status')), `status: ${await text('#status')}`);
    });

    await check('language: the choice survives a reload, whatever the browser prefers', async () => {
      assert(page, 'no page');
      await page.reload();
      await settled(0);
      assert(await page.$eval('html', (e) => e.lang) === 'en', 'English was not kept');
      assert((await headings()).includes('Model'), `headings: ${await headings()}`);
      await andFrame(() => page.click('[data-language="ru"]'));
      assert((await headings()).includes('Модель'), `headings: ${await headings()}`);
      await page.reload();
      await settled(0);
      assert(await page.$eval('html', (e) => e.lang) === 'ru', 'Russian was not kept');
      assert(await text('#theory-toggle') === 'Теория', `theory button: ${await text('#theory-toggle')}`);
    });

    await check('presentation view: the picture and the step text larger at 1920×1080; P and Escape', async () => {
      assert(page, 'no page');
      await page.setViewportSize({ width: 1920, height: 1080 });
      await andFrame(() => page.click('#step-forward'));
      const measure = () => page.evaluate(() => ({
        picture: document.querySelector('.main-picture .stack').getBoundingClientRect().width,
        text: parseFloat(getComputedStyle(document.querySelector('#step-text')).fontSize),
        controls: parseFloat(getComputedStyle(document.querySelector('.controls')).fontSize),
        on: document.body.classList.contains('presentation'),
      }));
      const normal = await measure();
      assert(!normal.on, 'the presentation view is on before it was asked for');
      await page.click('#presentation-toggle');
      const large = await measure();
      assert(large.on, 'the button did not switch the presentation view on');
      assert(large.picture > normal.picture * 1.08, `the picture: ${normal.picture} px, ${large.picture} px presenting`);
      assert(large.text >= normal.text * 1.8, `the step text: ${normal.text} px, ${large.text} px presenting`);
      assert(large.controls < normal.controls, `the controls: ${normal.controls} px, ${large.controls} px presenting`);
      const bottom = await page.$eval('.main-picture .stack', (e) => e.getBoundingClientRect().bottom);
      assert(bottom <= 1080, `the picture ends at ${bottom} px, below the window`);
      assert(await page.evaluate(() => JSON.parse(localStorage.getItem('hsr-view-settings')).presentation) === true,
        'the presentation view is not kept in the settings');
      await page.keyboard.press('Escape');
      assert(!(await measure()).on, 'Escape did not leave the presentation view');
      await page.focus('#canvas');
      await page.keyboard.press('p');
      assert((await measure()).on, 'P did not switch the presentation view on');
      await page.focus('#step-number');
      await page.keyboard.press('p');
      assert((await measure()).on, 'P typed into the step number box switched the view');
      await page.reload();
      await settled(0);
      assert((await measure()).on, 'the presentation view did not survive a reload');
      await page.focus('#canvas');
      await page.keyboard.press('Escape');
      assert(!(await measure()).on, 'Escape did not leave the presentation view after a reload');
    });
  } finally {
    await own?.browser.close();
    if (server && server.exitCode === null) server.kill('SIGTERM');
  }
};
