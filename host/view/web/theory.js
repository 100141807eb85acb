// The theory pane: the algorithm's page (GET /api/theory/<name>?lang=, in the page's language), its
// links kept inside the viewer, and the pseudocode lines and flowchart boxes of the shown step's
// phase highlighted. The server renders the page, pseudocode and flowchart included
// (host/view/server/theory_markdown.cpp); this module only places and marks them.

import { language, tr } from './i18n.js';

const THEORY_LINK = /^\/docs\/theory\/(en|ru)\/([A-Za-z0-9_][A-Za-z0-9_.-]*)\.md$/;

export class TheoryPane {
  // pane: the <aside>; getJson(url): the api's GET.
  constructor(pane, getJson) {
    this.pane = pane;
    this.getJson = getJson;
    this.cache = new Map();   // "<lang>/<name>" -> the answer
    this.algorithm = null;    // the chosen algorithm, whose page the pane shows unless a link led elsewhere
    this.shownName = null;    // the page in the pane
    this.phase = null;        // the shown step's phase
    this.serial = 0;          // the latest load; an older one that ends later is dropped
    pane.addEventListener('click', (e) => this.click(e));
  }

  // Shows the page of that algorithm (again, for a new language).
  show(algorithm) {
    this.algorithm = algorithm;
    return this.load(algorithm);
  }

  reload() {
    return this.load(this.shownName ?? this.algorithm);
  }

  async load(name) {
    if (!name) return;
    const serial = ++this.serial;
    const key = `${language()}/${name}`;
    try {
      if (!this.cache.has(key)) {
        this.cache.set(key, await this.getJson(`/api/theory/${encodeURIComponent(name)}?lang=${language()}`));
      }
      if (serial !== this.serial) return;
      this.place(name, this.cache.get(key));
    } catch (e) {
      if (serial !== this.serial) return;
      this.cache.delete(key);
      this.shownName = name;
      this.pane.textContent = tr({ en: `no theory page: ${e.message}`, ru: `страницы нет: ${e.message}` });
    }
  }

  place(name, page) {
    this.shownName = name;
    this.pane.innerHTML = page.html;
    this.pane.dataset.page = name;
    this.pane.lang = page.language || language();
    for (const a of this.pane.querySelectorAll('a[href]')) {
      const href = a.getAttribute('href');
      if (href.startsWith('#') || THEORY_LINK.test(href)) continue;
      a.target = '_blank';  // other docs and external pages open beside the viewer
      a.rel = 'noopener';
    }
    if (name !== this.algorithm) {
      const back = document.createElement('p');
      back.className = 'theory-back';
      const link = document.createElement('a');
      link.href = '#';
      link.dataset.back = '1';
      link.textContent = tr({ en: `← back to ${this.algorithm}`, ru: `← назад к ${this.algorithm}` });
      back.append(link);
      this.pane.prepend(back);
    }
    this.highlight(false);
  }

  click(e) {
    const a = e.target.closest('a[href]');
    if (!a || !this.pane.contains(a)) return;
    if (a.dataset.back) {
      e.preventDefault();
      this.load(this.algorithm);
      return;
    }
    const match = THEORY_LINK.exec(a.getAttribute('href'));
    if (!match) return;
    e.preventDefault();
    this.load(match[2]);
    this.pane.scrollTop = 0;
  }

  // The shown step's phase, or null for the full render and for plugins without phases.
  setPhase(phase) {
    this.phase = phase || null;
    this.highlight(true);
  }

  highlight(scroll) {
    for (const el of this.pane.querySelectorAll('.current-phase')) el.classList.remove('current-phase');
    if (!this.phase || this.shownName !== this.algorithm) return;
    const marked = [...this.pane.querySelectorAll('[data-phase]')].filter((el) => el.dataset.phase === this.phase);
    for (const el of marked) el.classList.add('current-phase');
    if (scroll && marked.length && !this.pane.hidden) this.scrollTo(marked);
  }

  // Scrolls the pane (never the page) so that the first marked line shows, and its flowchart box too
  // when both fit in the pane.
  scrollTo(marked) {
    const pane = this.pane;
    const line = marked.find((el) => el.tagName === 'LI') ?? marked[0];
    const node = marked.find((el) => el.tagName.toLowerCase() === 'g');
    const box = pane.getBoundingClientRect();
    const rect = (el) => {
      const r = el.getBoundingClientRect();
      return { top: r.top - box.top + pane.scrollTop, bottom: r.bottom - box.top + pane.scrollTop };
    };
    let want = rect(line);
    if (node) {
      const n = rect(node);
      const both = { top: Math.min(want.top, n.top), bottom: Math.max(want.bottom, n.bottom) };
      if (both.bottom - both.top <= pane.clientHeight - 16) want = both;
    }
    const margin = 8;
    if (want.top < pane.scrollTop + margin) pane.scrollTop = Math.max(0, want.top - margin);
    else if (want.bottom > pane.scrollTop + pane.clientHeight - margin) pane.scrollTop = want.bottom - pane.clientHeight + margin;
  }
}
