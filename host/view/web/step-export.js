// Export of a range of steps, for slides: the page shows the hsr render command line that writes
// the steps from..to of the current view as numbered PNGs (hsr render --step A..B, docs/cli.md),
// with a copy button. A browser cannot zip files without a library; the command line can, and
// it is fast.

import { tr, onLanguageChange } from './i18n.js';

// hsr render renders each step of a range again up to it: it takes at most this many.
export const MAX_EXPORT_STEPS = 1000;

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
    fields.append(this.fromLabel, this.toLabel, this.copy);
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
    onLanguageChange(() => this.show());
    this.show();
  }

  // The command's words up to the step range: hsr render MODEL -a ... --width ... (app.js).
  // null hides the control: hidden-line plugins draw their steps in the page only.
  setBase(words) {
    this.baseWords = words;
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
    this.copy.textContent = tr({ en: 'copy', ru: 'копировать' });
    if (this.steps.total) {
      this.from.max = String(this.steps.total);
      this.to.max = String(this.steps.total);
    }
    const r = this.range();
    const text = this.commandText();
    this.command.textContent = text ?? '';
    this.copy.disabled = !text;
    this.note.textContent = r.error ?? (r.from !== undefined ? tr({
      en: `step-000.png is step ${r.from}, step-001.png step ${r.from + 1}, …; each step renders the algorithm again up to it`,
      ru: `step-000.png — шаг ${r.from}, step-001.png — шаг ${r.from + 1} и т. д.; каждый шаг алгоритм проходит заново с начала`,
    }) : '');
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
