// Export of a range of steps, for slides: a download of the steps from..to of the current view as
// a ZIP of numbered PNGs, which the server renders (POST /api/steps-zip, docs/viewer.md), and the
// hsr render command line that writes them on the machine that has hsr (hsr render --step A..B,
// docs/cli.md), with a copy button.

import { tr, onLanguageChange } from './i18n.js';
import { postForFile } from './api.js';

// hsr render renders each step of a range again up to it: it takes at most this many.
export const MAX_EXPORT_STEPS = 1000;
// The server's bound on one download (kMaxZipSteps in view_frames.hpp).
export const MAX_DOWNLOAD_STEPS = 200;

export class StepExport {
  // stepBox: the step bar (#steps); steps: the StepControls (total, current).
  constructor(stepBox, steps) {
    this.steps = steps;
    this.baseWords = null;
    this.box = document.createElement('details');
    this.box.id = 'step-export';
    this.box.className = 'step-export';
    this.summary = document.createElement('summary');
    const fields = document.createElement('div');
    fields.className = 'step-export-fields';
    this.fromLabel = document.createElement('label');
    this.toLabel = document.createElement('label');
    this.from = numberField('step-export-from');
    this.to = numberField('step-export-to');
    this.fromText = document.createTextNode('');
    this.toText = document.createTextNode('');
    this.fromLabel.append(this.fromText, ' ', this.from);
    this.toLabel.append(this.toText, ' ', this.to);
    this.copy = document.createElement('button');
    this.copy.type = 'button';
    this.copy.id = 'step-export-copy';
    this.copy.className = 'secondary';
    this.download = document.createElement('button');
    this.download.type = 'button';
    this.download.id = 'step-export-zip';
    this.download.className = 'secondary';
    this.downloading = false;
    fields.append(this.fromLabel, this.toLabel, this.download, this.copy);
    this.command = document.createElement('code');
    this.command.id = 'step-export-command';
    this.command.className = 'step-export-command';
    this.note = document.createElement('div');
    this.note.id = 'step-export-note';
    this.note.className = 'step-export-note';
    this.box.append(this.summary, fields, this.command, this.note);
    stepBox.append(this.box);

    this.box.addEventListener('toggle', () => {
      if (this.box.open) this.fillRange();
    });
    for (const field of [this.from, this.to]) field.addEventListener('input', () => this.show());
    this.copy.addEventListener('click', () => this.copyCommand());
    this.download.addEventListener('click', () => this.downloadZip());
    onLanguageChange(() => this.show());
    this.show();
  }

  // The command's words up to the step range: hsr render MODEL -a ... --width ... (app.js).
  // null hides the control: hidden-line plugins draw their steps in the page only.
  // request: the page's frame request of the picture shown, which the download renders step by step.
  setBase(words, request = null) {
    this.baseWords = words;
    this.request = request;
    this.box.hidden = !words;
    this.show();
  }

  // From the first step to the one shown (to the last when the full render is shown).
  fillRange() {
    const last = this.steps.current ?? this.steps.total ?? 1;
    this.to.value = String(last);
    this.from.value = String(Math.max(1, last - MAX_EXPORT_STEPS + 1));
    this.show();
  }

  range() {
    const from = Number(this.from.value);
    const to = Number(this.to.value);
    if (!Number.isInteger(from) || !Number.isInteger(to) || from < 1 || to < 1) {
      return { error: tr({ en: 'steps count from 1', ru: 'шаги нумеруются с 1' }) };
    }
    if (to < from) return { error: tr({ en: 'the range ends before it starts', ru: 'конец диапазона раньше его начала' }) };
    if (to - from >= MAX_EXPORT_STEPS) {
      return { error: tr({ en: `at most ${MAX_EXPORT_STEPS} steps at a time`, ru: `не больше ${MAX_EXPORT_STEPS} шагов за раз` }) };
    }
    return { from, to };
  }

  commandText() {
    const r = this.range();
    if (!this.baseWords || r.error) return null;
    return [...this.baseWords, `--step ${r.from}..${r.to}`, '-o', "'step-%03d.png'"].join(' ');
  }

  show() {
    this.summary.textContent = tr({ en: 'export steps', ru: 'экспорт шагов' });
    this.summary.title = tr({
      en: 'the command line that writes a range of steps as PNG files, for slides',
      ru: 'командная строка, которая сохраняет диапазон шагов в файлы PNG — для слайдов',
    });
    this.fromText.textContent = tr({ en: 'from', ru: 'с' });
    this.toText.textContent = tr({ en: 'to', ru: 'по' });
    this.copy.textContent = tr({ en: 'copy command', ru: 'копировать команду' });
    this.download.textContent = this.downloading
      ? tr({ en: 'rendering the steps…', ru: 'шаги рисуются…' })
      : tr({ en: 'download ZIP', ru: 'скачать ZIP' });
    this.download.title = tr({
      en: `the steps as PNG files in one ZIP archive, rendered by the server (at most ${MAX_DOWNLOAD_STEPS} steps)`,
      ru: `шаги в файлах PNG одним архивом ZIP; их рисует сервер (не больше ${MAX_DOWNLOAD_STEPS} шагов)`,
    });
    if (this.steps.total) {
      this.from.max = String(this.steps.total);
      this.to.max = String(this.steps.total);
    }
    const r = this.range();
    const text = this.commandText();
    this.command.textContent = text ?? '';
    this.copy.disabled = !text;
    const tooMany = !r.error && r.to - r.from >= MAX_DOWNLOAD_STEPS;
    this.download.disabled = !text || !this.request || tooMany || this.downloading;
    if (this.downloading) return;
    this.note.textContent = r.error ?? (tooMany ? tr({
      en: `a download holds at most ${MAX_DOWNLOAD_STEPS} steps; the command line writes up to ${MAX_EXPORT_STEPS}`,
      ru: `в архив входит не больше ${MAX_DOWNLOAD_STEPS} шагов; командная строка сохраняет до ${MAX_EXPORT_STEPS}`,
    }) : r.from !== undefined ? tr({
      en: `the ZIP: step-001.png is step ${r.from}, step-002.png step ${r.from + 1}, …; the command: step-000.png is step ${r.from}, …; each step renders the algorithm again up to it`,
      ru: `в архиве step-001.png — шаг ${r.from}, step-002.png — шаг ${r.from + 1} и т. д.; у команды step-000.png — шаг ${r.from}; каждый шаг алгоритм проходит заново с начала`,
    }) : '');
  }

  // The server renders the steps and answers with the ZIP, which the browser saves.
  async downloadZip() {
    const r = this.range();
    if (r.error || !this.request || this.downloading) return;
    const request = { ...this.request, step: null, buffers: [], from: r.from, to: r.to };
    this.downloading = true;
    this.show();
    this.note.textContent = tr({
      en: `the server renders steps ${r.from}..${r.to}…`,
      ru: `сервер рисует шаги ${r.from}..${r.to}…`,
    });
    let message;
    try {
      const { blob, name } = await postForFile('/api/steps-zip', request, `${request.algorithm}-steps-${r.from}-${r.to}.zip`);
      const link = document.createElement('a');
      link.href = URL.createObjectURL(blob);
      link.download = name;
      document.body.append(link);
      link.click();
      link.remove();
      setTimeout(() => URL.revokeObjectURL(link.href), 60000);
      message = tr({ en: `saved ${name}`, ru: `сохранён файл ${name}` });
    } catch (e) {
      message = e.message;
    }
    this.downloading = false;
    this.show();
    this.note.textContent = message;
  }

  async copyCommand() {
    const text = this.commandText();
    if (!text) return;
    try {
      await navigator.clipboard.writeText(text);
      this.note.textContent = tr({ en: 'command copied', ru: 'команда скопирована' });
    } catch {
      const selection = window.getSelection();
      selection.selectAllChildren(this.command);
      this.note.textContent = tr({ en: 'the command is selected: copy it with Ctrl+C', ru: 'команда выделена — скопируйте её (Ctrl+C)' });
    }
  }
}

function numberField(id) {
  const field = document.createElement('input');
  field.type = 'number';
  field.id = id;
  field.min = '1';
  field.step = '1';
  return field;
}
