// The scene editor on a page in Russian (a browser whose locale is ru-RU): a mistyped statement
// shows the scene reader's message in Russian beside its line («строка N: неизвестная инструкция
// «lihgt»»), an empty text the server's own message in Russian; switching the page to English asks
// for the message again, now the English one the command line prints.

import fs from 'node:fs';
import path from 'node:path';

export default async (h) => {
  const { check, assert } = h;
  const { browser, page } = await h.newBrowser({ locale: 'ru-RU' });
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
  const lineError = () => page.$eval('#scene-line-error', (e) => ({ hidden: e.hidden, line: e.dataset.line, text: e.textContent }));
  const cyrillic = /[\u0400-\u04FF]/;

  try {
    await idle();
    const exercise = await h.modelOption(page, 'zbuffer-exercise.scene');
    assert(exercise, 'zbuffer-exercise.scene is not in the model list');
    await andFrame(() => page.selectOption('#model', exercise));
    await page.click('#scene-editor summary');
    await page.waitForFunction(() => document.querySelector('#scene-text').value.length > 0, null, { timeout: 10_000 });
    assert(await page.$eval('#scene-editor summary', (e) => e.textContent) === 'Редактор сцены', 'the page is not in Russian');

    const lines = exerciseText.split('\n');
    const index = lines.findIndex((l) => l.trim().startsWith('vertex'));
    assert(index >= 0, 'the exercise has no vertex line');
    lines.splice(index, 0, 'lihgt point:1,2,3');
    const broken = lines.join('\n');
    const brokenLine = index + 1;

    await check('a mistyped statement shows the Russian message at its line', async () => {
      await page.fill('#scene-text', broken);
      await page.waitForFunction(() => !document.querySelector('#scene-line-error').hidden, null, { timeout: 30_000 });
      await idle();
      const shown = await lineError();
      assert(shown.line === String(brokenLine), `the error is on line ${shown.line}, the broken line is ${brokenLine}: ${shown.text}`);
      assert(shown.text === `строка ${brokenLine}: неизвестная инструкция «lihgt»`, `message: "${shown.text}"`);
      const bad = await page.$eval('#scene-lines span.bad', (s) => s.dataset.line);
      assert(bad === String(brokenLine), `line ${bad} is marked`);
    });

    await check('switched to English, the same error reads in English', async () => {
      await page.click('[data-language="en"]');
      await page.waitForFunction((n) => {
        const e = document.querySelector('#scene-line-error');
        return !e.hidden && e.textContent.startsWith(`${n}: unknown`);
      }, brokenLine, { timeout: 30_000 }).catch(() => {});
      const shown = await lineError();
      assert(shown.text === `${brokenLine}: unknown statement 'lihgt'`, `message: "${shown.text}"`);
      await page.click('[data-language="ru"]');
      await page.waitForFunction(() => /[\u0400-\u04FF]/.test(document.querySelector('#scene-line-error').textContent),
        null, { timeout: 30_000 }).catch(() => {});
      const again = await lineError();
      assert(again.text === `строка ${brokenLine}: неизвестная инструкция «lihgt»`, `back in Russian: "${again.text}"`);
    });

    await check('a polygon error and a light error read in Russian at their lines', async () => {
      const withLight = exerciseText.trimEnd() + '\nlight point:1,2\n';
      const lightLine = withLight.trimEnd().split('\n').length;
      await page.fill('#scene-text', withLight);
      await page.waitForFunction((n) => document.querySelector('#scene-line-error').dataset.line === String(n),
        lightLine, { timeout: 30_000 });
      const shown = await lineError();
      assert(shown.text.startsWith(`строка ${lightLine}: источник света «point:1,2»: нужны три координаты x,y,z`),
        `message: "${shown.text}"`);
    });

    await check('an empty text gets the server\'s message in Russian', async () => {
      const errors = [];
      page.on('response', async (r) => {
        if (r.url().includes('/api/upload') && r.status() === 400) errors.push((await r.json()).error);
      });
      await page.fill('#scene-text', '');
      await page.waitForFunction(() => window.hsrView.idle(), null, { timeout: 30_000 });
      await page.waitForTimeout(800);
      assert(errors.length > 0, 'no upload was refused');
      assert(cyrillic.test(errors[0]) && !/body is empty/.test(errors[0]), `upload error: "${errors[0]}"`);
    });

    await andFrame(() => page.fill('#scene-text', exerciseText));
    assert((await lineError()).hidden, 'the error stays after the text is mended');
  } finally {
    await browser.close();
  }
};
