// Every word of the Russian page is Russian, in a page of its own (locale ru-RU, 1280×800): with
// zbuffer at a step, with the theory pane, the scene editor and the look-at camera open; with
// zbuffer beside scanline-zbuffer; with roberts at a step; and with roberts beside appel. In each
// state it reads every text a person sees (text nodes of shown elements, every option of a shown
// select, and the placeholder, title, aria-label, alt and button values) and fails on a word in
// Latin letters, naming each word and where it is.
//
// Latin letters that are not English words are let through, each for its reason:
// - text inside <code>, <kbd>, <pre>, <samp> and the editor's <textarea>: command lines, file
//   syntax and key names as typed;
// - the theory page's list of sources (Литература): papers are cited under their own titles;
// - plugin, lighting and model names, and file names and paths (they name a file or a plugin as
//   the command line does);
// - the program's name (hsr view, the page's title and heading);
// - single letters, with an index or a power (the variables x, y, z, n² of formulas and
//   coordinates), numbers with an exponent, and the reflection coefficients ka, kd, ks, written as
//   the textbooks write them;
// - in the theory page, an English term in parentheses beside its Russian one, «Z-конфликты
//   (z-fighting)», as a Russian textbook gives it;
// - the names in NAMES below: the program's name, language codes, file formats and key caps;
// - a plugin's own texts (description, parameter name and help, choices, phase titles, counters,
//   step buffers, step types) that the plugin gives no Russian for in /api/plugins' `translations`;
//   where it gives one, the page must show it.

// The counters the host adds to every plugin's (framework/src/pipeline.cpp, fragment_lists.cpp,
// lines.cpp): the page has Russian names for them.
const HOST_COUNTERS = new Set(['fragments-shaded', 'shading-batches', 'fragments', 'edges-requested']);

const NAMES = new Set([
  // the program, and the language buttons' language codes
  'hsr', 'EN', 'RU',
  // file formats
  'PNG', 'OBJ', 'OFF', 'PLY', 'STL', 'glTF', 'GLB',
  // key caps, as the keyboard prints them
  'Esc', 'Shift', 'Home', 'End', 'Enter', 'Ctrl', 'Alt', 'P',
]);

const FILE_NAME = /^\.?[\w-]+(\.[\w-]+)*\.(scene|obj|off|ply|stl|glb|gltf|md|png|json|so|dll|dylib)$/i;
const EXTENSION = /^\.(scene|obj|off|ply|stl|glb|gltf|md|png|json)$/i;
const VARIABLE = /^[A-Za-z][\d²³⁰-⁹]*$|^(?:[A-Za-z][\d²³⁰-⁹₀-₉]+(?:\.\.)?)+$|^k[ads]$/;
const NUMBER = /^[\d.,]*\d[eE][-+]?\d+$/;
const CYRILLIC = /[\u0400-\u04FF]/;
const LATIN = /[A-Za-z]/;

// Every text a person reads in the page now, as [{text, where}].
function pageTexts(page) {
  return page.evaluate(() => {
    const CODE = 'code, kbd, pre, samp, textarea, script, style';
    const shown = (el) => el.checkVisibility({ checkOpacity: true, checkVisibilityCSS: true });
    const where = (el) => {
      const parts = [];
      for (let e = el; e && e !== document.body && parts.length < 3; e = e.parentElement) {
        parts.unshift(e.id ? `#${e.id}` : `${e.localName}${e.classList.length ? `.${[...e.classList].join('.')}` : ''}`);
        if (e.id) break;
      }
      return parts.join(' ');
    };
    // An option is read when its select is opened: it counts when the select is shown.
    const read = (el) => {
      const select = el.closest('select');
      return select ? shown(select) : shown(el);
    };
    // The theory page's list of sources cites books and papers under their own titles.
    const inSources = (el) => {
      let block = el;
      while (block.parentElement && !block.parentElement.querySelector(':scope > h2')) block = block.parentElement;
      for (let e = block; e; e = e.previousElementSibling) {
        if (e.localName === 'h2') return /^(Литература|Источники)$/.test(e.textContent.trim());
      }
      return false;
    };
    const out = document.title === 'hsr view' ? [] : [{ text: document.title, where: 'the tab\'s title' }];
    const walker = document.createTreeWalker(document.body, NodeFilter.SHOW_TEXT);
    for (let node = walker.nextNode(); node; node = walker.nextNode()) {
      const el = node.parentElement;
      const text = node.textContent.trim();
      if (!text || el.closest(CODE) || el.closest('header h1') || !read(el)) continue;
      const theory = Boolean(el.closest('#theory'));
      if (!(theory && inSources(el))) out.push({ text, where: where(el), theory });
    }
    for (const el of document.body.querySelectorAll('*')) {
      if (el.closest('script, style') || !read(el)) continue;
      // A stats row's title is the counter's name as --stats prints it.
      const attributes = el.matches('.stats td') ? ['alt', 'placeholder'] : ['title', 'alt', 'placeholder'];
      if (!el.closest('[aria-hidden="true"]')) attributes.push('aria-label');
      if (el.localName === 'optgroup') attributes.push('label');
      if (el.matches('input[type="button"], input[type="submit"], input[type="reset"]')) attributes.push('value');
      for (const name of attributes) {
        const text = el.getAttribute(name)?.trim();
        if (text) out.push({ text, where: `${where(el)} [${name}]` });
      }
    }
    return out;
  });
}

// The counters of the stats tables (as --stats names them), the step buffers of the page's last
// answer and the kinds of step the step bar offers to jump by, for the plugin texts.
function answerNames(page) {
  return page.evaluate(() => {
    const counters = new Set([...document.querySelectorAll('.stats tr > td:first-child')]
      .map((cell) => cell.title || cell.textContent.trim()));
    const buffers = new Set();
    const types = [...document.querySelectorAll('#step-by option')].map((o) => o.value)
      .filter((v) => v.startsWith('type:')).map((v) => v.slice(5));
    const walk = (value) => {
      if (!value || typeof value !== 'object') return;
      if (Array.isArray(value.buffers)) for (const b of value.buffers) if (typeof b?.name === 'string') buffers.add(b.name);
      for (const v of Object.values(value)) walk(v);
    };
    walk(window.hsrView.lastResponse);
    return { counters: [...counters], buffers: [...buffers], types };
  });
}

export default async (h) => {
  const { check, assert } = h;
  const { browser, page } = await h.newBrowser({ locale: 'ru-RU', viewport: { width: 1280, height: 800 } });
  const frame = () => page.$eval('#canvas', (c) => Number(c.dataset.frame));
  const settled = (after) => page.waitForFunction((n) => {
    const c = document.querySelector('#canvas');
    return window.hsrView && window.hsrView.idle() && Number(c.dataset.frame) > n && c.dataset.state !== 'loading';
  }, after, { timeout: 60_000 });
  const idle = () => page.waitForFunction(() => window.hsrView && window.hsrView.idle()
    && document.querySelector('#canvas').dataset.state !== 'loading', null, { timeout: 60_000 });
  const andFrame = async (action) => {
    const before = await frame();
    await action();
    await settled(before);
  };
  const showStep = (k) => andFrame(async () => {
    await page.fill('#step-number', String(k));
    await page.press('#step-number', 'Enter');
  });

  // What the plugins say in English only: whole texts, and names that stand alone.
  const plugins = await (await fetch(new URL('api/plugins', h.serverUrl), { headers: h.apiHeaders })).json();
  const all = [...plugins.hidden_surface, ...plugins.hidden_line, ...plugins.lighting];
  const russian = (p) => p.translations?.ru ?? {};
  const untranslatedTexts = new Set();  // descriptions, help, phase titles: found inside a text
  const untranslatedNames = new Set();  // parameter names, choices, phase names: a whole word
  const translatedNames = new Set();  // parameter names and choices the page must not show alone
  for (const p of all) {
    const ru = russian(p);
    if (!ru.description && p.description) untranslatedTexts.add(p.description.trim());
    // Parameter names and choices are also identifiers the command line takes (-p depth-test=less),
    // which a Russian text may name beside its words; shown alone they must be translated if they can.
    for (const param of p.params || []) {
      untranslatedNames.add(param.name);
      if (ru[`param:${param.name}`]) translatedNames.add(param.name);
      if (!ru[`help:${param.name}`] && param.help) untranslatedTexts.add(param.help.trim());
      for (const choice of param.choices || []) {
        untranslatedNames.add(choice);
        if (ru[`choice:${param.name}:${choice}`]) translatedNames.add(choice);
      }
    }
    for (const phase of p.phases || []) {
      if (!ru[`phase:${phase.name}`]) {
        untranslatedNames.add(phase.name);
        if (phase.title) untranslatedTexts.add(phase.title.trim());
      }
    }
  }
  const models = await (await fetch(new URL('api/models', h.serverUrl), { headers: h.apiHeaders })).json();
  const modelNames = new Set(JSON.stringify(models).match(/[\w.-]+\.(scene|obj|off|ply|stl|glb|gltf)\b/gi) || []);
  const pluginNames = new Set(all.map((p) => p.name));

  // The Latin words of the page's texts that nothing above lets through, with where they are.
  async function englishWords(shownPlugins) {
    const { counters, buffers, types } = await answerNames(page);
    const names = new Set(untranslatedNames);
    const lacks = (key) => shownPlugins.some((name) => !russian(all.find((p) => p.name === name) || {})[key]);
    for (const c of counters) if (!HOST_COUNTERS.has(c) && lacks(`counter:${c}`)) names.add(c);
    for (const b of buffers) if (lacks(`buffer:${b.replace(/-\d+$/, '')}`)) names.add(b);
    for (const t of types) if (lacks(`step:${t}`)) names.add(t);
    const found = [];
    for (const { text, where, theory } of await pageTexts(page)) {
      if (translatedNames.has(text) && !pluginNames.has(text)) found.push(`«${text}» (${where}: the plugin translates it)`);
      let rest = text;
      for (const plugin of untranslatedTexts) rest = rest.split(plugin).join(' ');
      if (theory) rest = rest.replace(/\((?:[A-Za-z][\w-]*\s*)+\)/g, ' ');
      for (const token of rest.match(/[\p{L}\p{N}_'’./-]+/gu) || []) {
        const word = token.replace(/^['’/-]+|[.'’/-]+$/g, '');
        if (!LATIN.test(word) || CYRILLIC.test(word)) continue;
        if (VARIABLE.test(word) || NUMBER.test(word) || NAMES.has(word)) continue;
        if (pluginNames.has(word) || modelNames.has(word) || names.has(word)) continue;
        if (FILE_NAME.test(word) || EXTENSION.test(word) || word.includes('/')) continue;
        found.push(`«${word}» (${where}: “${text.length > 60 ? `${text.slice(0, 57)}…` : text}”)`);
      }
    }
    return [...new Set(found)];
  }
  const noEnglish = async (state, shownPlugins) => {
    const words = await englishWords(shownPlugins);
    assert(words.length === 0, `${state}: ${words.length} words in Latin letters: ${words.join('; ')}`);
  };

  try {
    await settled(0);
    assert(await page.$eval('html', (e) => e.lang) === 'ru', 'the page is not in Russian');

    await check('russian words: zbuffer at a step, the theory, the editor and the look-at camera open', async () => {
      await andFrame(() => page.selectOption('#algorithm', 'zbuffer'));
      await page.waitForFunction(() => /\d/.test(document.querySelector('#step-total').textContent), null, { timeout: 60_000 });
      await showStep(3);
      await page.click('#theory-toggle');
      await page.waitForSelector('#theory:not([hidden]) h1', { timeout: 20_000 });
      await page.click('#scene-editor summary');
      await page.waitForFunction(() => document.querySelector('#scene-text').value.length > 0, null, { timeout: 20_000 });
      await page.click('#look-at summary');
      await idle();
      await noEnglish('zbuffer at step 3', ['zbuffer']);
    });

    await check('russian words: zbuffer beside scanline-zbuffer', async () => {
      await page.selectOption('#compare-algorithm', 'scanline-zbuffer');
      await andFrame(() => page.check('#compare-toggle'));
      try {
        await noEnglish('zbuffer beside scanline-zbuffer', ['zbuffer', 'scanline-zbuffer']);
      } finally {
        await andFrame(() => page.uncheck('#compare-toggle'));
      }
    });

    await check('russian words: roberts at a step', async () => {
      await andFrame(() => page.selectOption('#algorithm', 'roberts'));
      await page.waitForFunction(() => /\d/.test(document.querySelector('#step-total').textContent), null, { timeout: 60_000 });
      await showStep(5);
      await idle();
      await noEnglish('roberts at step 5', ['roberts']);
    });

    await check('russian words: roberts beside appel', async () => {
      await page.selectOption('#compare-algorithm', 'appel');
      await andFrame(() => page.check('#compare-toggle'));
      try {
        await noEnglish('roberts beside appel', ['roberts', 'appel']);
      } finally {
        await andFrame(() => page.uncheck('#compare-toggle'));
      }
    });

    await check('the file picker is the page\'s own, in its language, and uploads the file chosen', async () => {
      await andFrame(() => page.selectOption('#algorithm', 'zbuffer'));
      const text = async (selector) => (await page.textContent(selector)).trim();
      assert(await text('#upload-choose') === 'загрузить файл…', `button: ${await text('#upload-choose')}`);
      assert(await text('#upload-name') === 'файл не выбран', `file name: ${await text('#upload-name')}`);
      assert(await page.$eval('#upload', (input) => !input.checkVisibility()), 'the browser\'s own file input shows');
      const [chooser] = await Promise.all([page.waitForEvent('filechooser'), page.click('#upload-choose')]);
      await andFrame(() => chooser.setFiles({
        name: 'one-triangle.obj', mimeType: 'text/plain', buffer: Buffer.from('v 0 0 0\nv 1 0 0\nv 0 1 0\nf 1 2 3\n') }));
      assert((await page.$eval('#model', (s) => s.value)).startsWith('upload/'), 'the chosen file is not the model shown');
      assert(await text('#upload-name') === 'one-triangle.obj', `file name: ${await text('#upload-name')}`);
      await page.click('.language-choice button[data-language="en"]');
      assert(await text('#upload-choose') === 'upload a file…', `button in English: ${await text('#upload-choose')}`);
      assert(await text('#upload-name') === 'one-triangle.obj', `file name in English: ${await text('#upload-name')}`);
    });
  } finally {
    await browser.close();
  }
};
