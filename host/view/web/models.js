// The model list: the served models (/api/models) and the uploaded ones in one select, and the
// upload of a model file chosen or dropped anywhere on the page (POST /api/upload). The file picker
// is the page's own button and file name, in the page's language (the browser's own input speaks the
// browser's language); the <input type=file> it opens stays hidden.

import { uploadModel } from './api.js';
import { fillSelect } from './form.js';
import { tr, onLanguageChange } from './i18n.js';

const sizeText = (bytes) => (!bytes ? ''
  : bytes < 1e6 ? tr({ en: ` (${Math.ceil(bytes / 1024)} KB)`, ru: ` (${Math.ceil(bytes / 1024)} КБ)` })
    : tr({ en: ` (${(bytes / 1e6).toFixed(1)} MB)`, ru: ` (${(bytes / 1e6).toFixed(1).replace('.', ',')} МБ)` }));

export class ModelList {
  // select: the <select>; onUploaded(id) after an upload, onError(e), onStatus(text).
  constructor(select, { onUploaded, onError, onStatus }) {
    this.select = select;
    this.models = [];
    this.onUploaded = onUploaded;
    this.onError = onError;
    this.onStatus = onStatus;
    this.fileName = null;     // the last file uploaded, chosen or dropped
    this.nameElement = null;
  }

  // Wires the page's button to the hidden file input, and shows the last file's name in nameElement.
  acceptPicks(input, button, nameElement) {
    this.nameElement = nameElement;
    button.addEventListener('click', () => input.click());
    input.addEventListener('change', () => {
      if (input.files[0]) this.upload(input.files[0]);
      input.value = '';
    });
    onLanguageChange(() => this.showFileName());
    this.showFileName();
  }

  showFileName() {
    if (!this.nameElement) return;
    this.nameElement.textContent = this.fileName ?? tr({ en: 'no file chosen', ru: 'файл не выбран' });
    this.nameElement.title = this.fileName ?? '';
  }

  // Fills the select with `models`, choosing `selected` if it is there; returns the id chosen.
  set(models, selected) {
    this.models = models;
    const folders = new Map();
    for (const m of models) {
      const uploaded = m.id.startsWith('upload/');
      const folder = uploaded ? tr({ en: 'uploaded', ru: 'загруженные' }) : tr({ en: 'models', ru: 'модели' });
      if (!folders.has(folder)) folders.set(folder, []);
      folders.get(folder).push({ value: m.id, text: `${uploaded ? m.name : m.id.replace(/^\d+\//, '')}${sizeText(m.bytes)}` });
    }
    return fillSelect(this.select, [...folders.entries()], selected) || null;
  }

  async upload(file) {
    this.fileName = file.name;
    this.showFileName();
    this.onStatus(tr({ en: `uploading ${file.name}…`, ru: `загрузка ${file.name}…` }));
    try {
      const { id } = await uploadModel(file);
      this.set([...this.models, { id, name: file.name, bytes: file.size }], id);
      this.onUploaded(id);
    } catch (e) {
      this.onError(e);
    }
  }

  // A file dragged over the window shows `target`; dropping it uploads it.
  acceptDrops(target) {
    let depth = 0;
    window.addEventListener('dragenter', (e) => {
      if (![...(e.dataTransfer?.types || [])].includes('Files')) return;
      depth += 1;
      target.hidden = false;
    });
    window.addEventListener('dragleave', () => {
      depth = Math.max(0, depth - 1);
      if (depth === 0) target.hidden = true;
    });
    window.addEventListener('dragover', (e) => e.preventDefault());
    window.addEventListener('drop', (e) => {
      e.preventDefault();
      depth = 0;
      target.hidden = true;
      const file = e.dataTransfer?.files?.[0];
      if (file) this.upload(file);
    });
  }
}
