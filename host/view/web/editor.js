// The scene editor: a .scene file's text (docs/scene-format.md) beside line numbers, rendered again
// a moment after each edit. Each edit goes to the server as a .scene upload that replaces the
// editor's previous one (POST /api/upload with X-Replaces, and X-Base-Model naming the served scene
// it came from, for its relative mesh paths), and the page renders that model; a
// scene the server cannot read keeps the last good picture and shows its message beside the line
// at fault, in the page's language (?lang= on the editor's requests, "language" in the frame's). The
// textbook exercises are starting points, and the text downloads as a .scene file.

import { ApiError } from './api.js';
import { LatestWins } from './scheduler.js';
import { language, onLanguageChange, tr } from './i18n.js';

const EDIT_DELAY_MS = 300;
const FILE_NAME = 'scene-editor.scene';
export const STARTING_POINTS = [
  'zbuffer-exercise.scene', 'zbuffer-exercise-50.scene', 'three-polygons.scene', 'boxes.scene',
];

// The line a scene error names ("…/name.scene:12: message"), or null.
export function sceneErrorLine(message) {
  const match = /\.scene:(\d+):\s*(.*)$/s.exec(String(message));
  return match ? { line: Number(match[1]), text: match[2] } : null;
}

async function answerError(response) {
  let message = `HTTP ${response.status}`;
  try {
    const body = await response.json();
    if (body && typeof body.error === 'string') message = body.error;
  } catch { /* not JSON */ }
  return new ApiError(message, response.status, null);
}

export class SceneEditor {
  // root: an empty element; models(): the served models [{id}]; currentModel(): the page's model id;
  // show(id, name, bytes, replacedId): render that model; onError(e): an error that is not the scene's.
  constructor(root, { models, currentModel, show, onError }) {
    this.models = models;
    this.currentModel = currentModel;
    this.show = show;
    this.onError = onError;
    this.uploadedId = null;
    this.baseModel = null;
    this.timer = null;
    this.build(root);
    this.uploads = new LatestWins((text) => this.send(text), () => {}, 5000);
    onLanguageChange(() => {
      this.applyTexts();
      // The scene's message is asked for again in the new language.
      if (this.error && this.text.value) this.uploads.submit(this.text.value);
    });
    this.applyTexts();
  }

  build(root) {
    root.innerHTML = `
      <details id="scene-editor" class="scene-editor">
        <summary data-text="heading"></summary>
        <div class="row scene-tools">
          <select id="scene-start"></select>
          <a id="scene-download" class="button secondary" download="${FILE_NAME}" href="#"></a>
        </div>
        <div class="scene-code">
          <pre id="scene-lines" class="scene-lines" aria-hidden="true"></pre>
          <textarea id="scene-text" spellcheck="false" wrap="off" autocomplete="off"></textarea>
          <div id="scene-line-error" class="scene-line-error" role="alert" hidden></div>
        </div>
        <p class="hint" data-text="hint"></p>
      </details>`;
    const $ = (id) => root.querySelector(`#${id}`);
    this.details = $('scene-editor');
    this.start = $('scene-start');
    this.download = $('scene-download');
    this.lines = $('scene-lines');
    this.text = $('scene-text');
    this.lineError = $('scene-line-error');
    this.root = root;
    this.details.addEventListener('toggle', () => {
      if (this.details.open && !this.text.value) this.openModel(this.currentModel());
    });
    this.text.addEventListener('input', () => {
      this.numberLines();
      clearTimeout(this.timer);
      this.timer = setTimeout(() => this.uploads.submit(this.text.value), EDIT_DELAY_MS);
    });
    this.text.addEventListener('scroll', () => {
      this.lines.scrollTop = this.text.scrollTop;
      this.placeError();
    });
    this.start.addEventListener('change', () => {
      const name = this.start.value;
      this.start.value = '';
      const model = this.models().find((m) => !m.id.startsWith('upload/') && m.id.endsWith(`/${name}`));
      if (model) this.load(model.id, true);
    });
    this.download.addEventListener('click', () => {
      if (this.download.href.startsWith('blob:')) URL.revokeObjectURL(this.download.href);
      this.download.href = URL.createObjectURL(new Blob([this.text.value], { type: 'text/plain' }));
    });
    this.numberLines();
  }

  applyTexts() {
    const texts = {
      heading: tr({ en: 'Scene editor', ru: 'Редактор сцены' }),
      hint: tr({
        en: 'the picture follows the text as you type; docs/scene-format.md describes the statements',
        ru: 'рисунок обновляется по мере ввода; операторы описаны в docs/scene-format.md',
      }),
    };
    for (const el of this.root.querySelectorAll('[data-text]')) el.textContent = texts[el.dataset.text];
    this.download.textContent = tr({ en: 'download .scene', ru: 'скачать .scene' });
    this.download.title = tr({ en: 'save the text as a .scene file', ru: 'сохранить текст в файл .scene' });
    this.text.setAttribute('aria-label', tr({ en: 'the scene file\'s text', ru: 'текст файла сцены' }));
    this.start.replaceChildren(new Option(tr({ en: 'start from an exercise…', ru: 'начать с упражнения…' }), ''));
    for (const name of STARTING_POINTS) this.start.add(new Option(name, name));
    this.start.value = '';
    if (this.error) this.setError(this.error);
  }

  // Opens the editor with the text of a served .scene model; other models leave it as it is.
  openModel(id) {
    if (id && id.endsWith('.scene') && !id.startsWith('upload/')) this.load(id, false);
  }

  async load(id, render) {
    try {
      const response = await fetch(`/api/scene-text?model=${encodeURIComponent(id)}&lang=${language()}`);
      if (!response.ok) throw await answerError(response);
      this.text.value = await response.text();
      this.baseModel = id;
      this.numberLines();
      this.setError(null);
      if (render) {
        clearTimeout(this.timer);
        this.uploads.submit(this.text.value);
      }
    } catch (e) {
      this.onError(e);
    }
  }

  async send(text) {
    try {
      const headers = { 'X-File-Name': FILE_NAME, 'Content-Type': 'application/octet-stream' };
      if (this.uploadedId) headers['X-Replaces'] = this.uploadedId;
      // Its relative mesh paths stay those of the served scene it came from.
      if (this.baseModel) headers['X-Base-Model'] = this.baseModel;
      const response = await fetch(`/api/upload?lang=${language()}`, { method: 'POST', headers, body: text });
      if (!response.ok) throw await answerError(response);
      const { id } = await response.json();
      const replaced = this.uploadedId;
      this.uploadedId = id;
      this.show(id, FILE_NAME, new Blob([text]).size, replaced);
    } catch (e) {
      this.onError(e);
    }
  }

  // The page's frame of `model` was shown (error null) or failed with `error`.
  frameDone(model, error) {
    if (!model || model !== this.uploadedId) return;
    this.setError(error ? sceneErrorLine(error.message || error) || { line: null, text: String(error.message || error) } : null);
  }

  setError(error) {
    this.error = error;
    this.lineError.hidden = !error;
    const atLine = (line, text) => tr({ en: `${line}: ${text}`, ru: `строка ${line}: ${text}` });
    this.lineError.textContent = error ? (error.line ? atLine(error.line, error.text) : error.text) : '';
    this.lineError.dataset.line = error?.line ?? '';
    this.numberLines();
    this.placeError();
  }

  numberLines() {
    const count = this.text.value.split('\n').length;
    const bad = this.error?.line;
    this.lines.replaceChildren(...Array.from({ length: count }, (_, i) => {
      const span = document.createElement('span');
      span.textContent = String(i + 1);
      span.dataset.line = String(i + 1);
      if (bad === i + 1) span.className = 'bad';
      return span;
    }));
    this.lines.scrollTop = this.text.scrollTop;
  }

  // The message sits on the line at fault (below the text when the error names no line).
  placeError() {
    if (this.lineError.hidden) return;
    const line = this.error?.line;
    const span = line ? this.lines.querySelector(`[data-line="${line}"]`) : null;
    if (span) {
      this.lineError.style.top = `${span.offsetTop - this.text.scrollTop}px`;
      this.lineError.classList.remove('below');
    } else {
      this.lineError.style.top = '';
      this.lineError.classList.add('below');
    }
  }
}
