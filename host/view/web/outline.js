// The outline of a run's steps (POST /api/steps): the steps grouped into runs of the same type,
// phase and level. It gives the step bar its coarse units (the next phase, level, culled node, …)
// and where a step lies in the run, and it fills the worked example of the theory pane.

import { tr, pluginText } from './i18n.js';

// The unit one coarse step moves by: 'step', 'phase', 'level' or 'type:<name>'.
export class StepOutline {
  // answer: /api/steps; plugin: the algorithm's /api/plugins entry, for its names of step types.
  constructor(answer, plugin = null) {
    this.plugin = plugin;
    this.total = answer.total;
    this.runs = answer.runs;          // [first, count, type, phase, level]
    this.truncated = answer.truncated;
    this.firsts = answer.firsts;
    this.width = answer.width;
    this.height = answer.height;
    this.triangles = answer.triangles;
    this.types = [...new Set(this.runs.map((run) => run[2]))];
    this.phases = [...new Set(this.runs.map((run) => run[3]).filter((phase) => phase !== null))];
    this.hasLevels = this.runs.some((run) => run[4] !== null);
  }

  // The index of the run that holds step k, or -1 past the runs (a truncated outline).
  runOf(k) {
    let lo = 0;
    let hi = this.runs.length - 1;
    if (hi < 0 || k < this.runs[0][0]) return -1;
    while (lo < hi) {
      const mid = (lo + hi + 1) >> 1;
      if (this.runs[mid][0] <= k) lo = mid;
      else hi = mid - 1;
    }
    const [first, count] = this.runs[lo];
    return k < first + count ? lo : -1;
  }

  // What the unit compares between runs.
  static key(unit) {
    if (unit === 'phase') return (run) => run[3];
    if (unit === 'level') return (run) => run[4];
    return (run) => run[2];
  }

  // The step one unit after (dir 1) or before (dir -1) step k, or null when there is none.
  // phase and level: the start of the next stretch of runs of another phase or level; back, the
  // start of the stretch k is in, or of the one before when k is its start. type:T: the next or
  // previous step of type T.
  move(k, unit, dir) {
    if (unit === 'step' || !unit) return clampStep(k + dir, this.total);
    const at = this.runOf(k);
    if (at < 0) return null;
    if (unit.startsWith('type:')) {
      const type = unit.slice(5);
      const near = this.runOf(k + dir);
      if (near >= 0 && this.runs[near][2] === type) return k + dir;
      for (let i = at + dir; i >= 0 && i < this.runs.length; i += dir) {
        const [first, count, runType] = this.runs[i];
        if (runType === type) return dir > 0 ? first : first + count - 1;
      }
      return null;
    }
    const key = StepOutline.key(unit);
    if (dir > 0) {
      const here = key(this.runs[at]);
      for (let i = at + 1; i < this.runs.length; i += 1) if (key(this.runs[i]) !== here) return this.runs[i][0];
      return null;
    }
    let start = this.stretchStart(at, key);
    if (this.runs[start][0] < k) return this.runs[start][0];
    if (start === 0) return null;
    start = this.stretchStart(start - 1, key);
    return this.runs[start][0];
  }

  stretchStart(at, key) {
    const here = key(this.runs[at]);
    let start = at;
    while (start > 0 && key(this.runs[start - 1]) === here) start -= 1;
    return start;
  }

  // The coarse units this run has, as [value, label].
  units() {
    const units = [['step', tr({ en: 'one step', ru: 'один шаг' })]];
    if (this.phases.length > 1) units.push(['phase', tr({ en: 'next phase', ru: 'следующий этап' })]);
    if (this.hasLevels) units.push(['level', tr({ en: 'next level', ru: 'следующий уровень' })]);
    for (const type of this.types) units.push([`type:${type}`, typeLabel(type, this.plugin)]);
    return units;
  }

  // "phase «…» · run 3 of 120" for step k, or '' when the outline does not reach it.
  where(k, phaseTitle) {
    const at = this.runOf(k);
    if (at < 0) return '';
    const [, , , phase, level] = this.runs[at];
    const parts = [];
    if (phase !== null) parts.push(tr({ en: `phase “${phaseTitle(phase)}”`, ru: `этап «${phaseTitle(phase)}»` }));
    if (level !== null) parts.push(tr({ en: `level ${level}`, ru: `уровень ${level}` }));
    const runs = this.runs.length.toLocaleString(tr({ en: 'en', ru: 'ru' }));
    parts.push(tr({ en: `run ${at + 1} of ${runs}`, ru: `серия ${at + 1} из ${runs}` })
      + (this.truncated ? tr({ en: ' (the outline stops there)', ru: ' (дальше серии не размечены)' }) : ''));
    return parts.join(' · ');
  }
}

function clampStep(k, total) {
  return Math.max(1, Math.min(k, total ?? k));
}

// The names of the step types the built-in plugins report, as a lecture says them.
const TYPE_LABELS = {
  'node-culled': { en: 'next culled node', ru: 'следующий отсечённый узел' },
  'node-visited': { en: 'next visited node', ru: 'следующий посещённый узел' },
  node: { en: 'next node', ru: 'следующий узел' },
  triangle: { en: 'next triangle', ru: 'следующий треугольник' },
  tile: { en: 'next tile', ru: 'следующая плитка' },
  'edge-begin': { en: 'next edge', ru: 'следующее ребро' },
};

// A step type's label: the plugin's own name for it in the page's language (ABI 1.6 key
// "step:<type>"), else the page's, else the type itself.
function typeLabel(type, plugin) {
  const own = pluginText(plugin, `step:${type}`, null);
  if (own) return tr({ en: `next step: ${own}`, ru: `следующий шаг: ${own}` });
  const known = TYPE_LABELS[type];
  return known ? tr(known) : tr({ en: `next “${type}”`, ru: `следующий шаг «${type}»` });
}

// The "step by" choice, the buttons that move by it and the line that says where the step lies,
// added to the step bar. controls: the page's StepControls; phaseTitle(name): a phase's title.
export class OutlineBar {
  constructor(stepBar, controls, phaseTitle) {
    this.controls = controls;
    this.phaseTitle = phaseTitle;
    this.outline = null;
    const label = document.createElement('label');
    label.className = 'step-by';
    this.labelText = document.createTextNode('');
    this.select = document.createElement('select');
    this.select.id = 'step-by';
    label.append(this.labelText, ' ', this.select);
    this.back = button('step-unit-back', BACK_ICON);
    this.forward = button('step-unit-forward', FORWARD_ICON);
    this.back.addEventListener('click', () => controls.go(this.move(-1, true) ?? controls.current));
    this.forward.addEventListener('click', () => controls.go(this.move(1, true) ?? controls.current));
    this.select.addEventListener('change', () => { this.unit = this.select.value; });
    this.unit = 'step';
    stepBar.append(label, this.back, this.forward);
    this.whereText = document.createElement('div');
    this.whereText.id = 'step-where';
    this.whereText.className = 'step-where';
    stepBar.after(this.whereText);
    this.keysHint = document.createElement('span');
    this.keysHint.className = 'keys-hint';
    this.keysHint.id = 'step-by-keys';
    stepBar.parentElement.querySelector('.keys-hint')?.after(this.keysHint);
    controls.mover = (k, dir) => (this.unit === 'step' || !this.outline ? undefined : this.move(dir, true, k));
    controls.onShown = () => this.showWhere();
    this.setOutline(null);
  }

  // The step one unit from step k (the step shown by default), for the keys and playing: fine
  // steps unless coarse; null when the unit has no step that way.
  move(dir, coarse, k = this.controls.current) {
    const from = k ?? (dir > 0 ? 0 : (this.controls.total ?? 1) + 1);
    if (!coarse || this.unit === 'step' || !this.outline) return clampStep(from + dir, this.controls.total);
    if (from < 1) return this.outline.runs.length ? this.firstOf(this.unit) : 1;
    if (from > this.outline.total) return this.outline.move(this.outline.total, this.unit, -1) ?? this.outline.total;
    return this.outline.move(from, this.unit, dir);
  }

  firstOf(unit) {
    if (unit.startsWith('type:')) return this.outline.firsts[unit]?.step ?? 1;
    return 1;
  }

  setOutline(outline) {
    this.outline = outline;
    this.labelText.textContent = tr({ en: 'step by', ru: 'шагать по' });
    this.back.title = tr({ en: 'back by the chosen unit (Shift+←)', ru: 'назад на выбранную единицу (Shift+←)' });
    this.forward.title = tr({ en: 'forward by the chosen unit (Shift+→)', ru: 'вперёд на выбранную единицу (Shift+→)' });
    this.back.setAttribute('aria-label', this.back.title);
    this.forward.setAttribute('aria-label', this.forward.title);
    this.keysHint.textContent = tr({ en: 'Shift+← → by the chosen unit', ru: 'Shift+← → на выбранную единицу' });
    const units = outline ? outline.units() : [['step', tr({ en: 'one step', ru: 'один шаг' })]];
    this.select.replaceChildren(...units.map(([value, text]) => new Option(text, value)));
    this.select.value = units.some(([value]) => value === this.unit) ? this.unit : 'step';
    this.unit = this.select.value;
    this.showWhere();
  }

  showWhere() {
    const k = this.controls.current;
    this.whereText.textContent = this.outline && k !== null ? this.outline.where(k, this.phaseTitle) : '';
  }
}

// Two arrowheads: a larger step than the bar's single ones.
const BACK_ICON = '<svg viewBox="0 0 16 16" width="14" height="14" aria-hidden="true"><path d="M8 3v10L1 8zM15 3v10L8 8z" fill="currentColor"/></svg>';
const FORWARD_ICON = '<svg viewBox="0 0 16 16" width="14" height="14" aria-hidden="true"><path d="M1 3v10l7-5zM8 3v10l7-5z" fill="currentColor"/></svg>';

function button(id, icon) {
  const b = document.createElement('button');
  b.type = 'button';
  b.id = id;
  b.innerHTML = icon;
  return b;
}

// Fills each empty worked-example block of the theory pane (div.worked-example) from the outline:
// the model, its triangles, the picture's size, the steps, and a table of the phases (of the kinds
// of step, for a plugin without phases) with each one's steps and first step, a button on which
// shows that step; then the first step's text.
export function fillWorkedExample(pane, outline, { modelName, phases, goToStep }) {
  for (const block of pane.querySelectorAll('div.worked-example')) {
    block.replaceChildren();
    if (!outline) continue;
    const n = (value) => Number(value).toLocaleString(tr({ en: 'en', ru: 'ru' }));
    const intro = document.createElement('p');
    intro.textContent = tr({
      en: `On “${modelName}” (${n(outline.triangles)} triangles) at ${outline.width}×${outline.height} pixels the algorithm takes ${n(outline.total)} steps.`,
      ru: `На модели «${modelName}» (треугольников: ${n(outline.triangles)}) при изображении ${outline.width}×${outline.height} пикселей алгоритм делает шагов: ${n(outline.total)}.`,
    });
    block.append(intro);
    // A row for each phase; for a plugin that names no phases, one for each type of step.
    const byPhase = outline.phases.length > 0;
    const column = byPhase ? 3 : 2;
    const counts = new Map();
    for (const run of outline.runs) if (run[column] !== null) counts.set(run[column], (counts.get(run[column]) ?? 0) + run[1]);
    const rows = byPhase ? phases.filter((phase) => counts.has(phase.name)) : [];
    for (const name of counts.keys()) if (!rows.some((row) => row.name === name)) rows.push({ name, title: name });
    if (rows.length) {
      const table = document.createElement('table');
      const head = table.createTHead().insertRow();
      const titles = [byPhase ? tr({ en: 'phase', ru: 'этап' }) : tr({ en: 'kind of step', ru: 'вид шага' }),
        tr({ en: 'steps', ru: 'шагов' }), tr({ en: 'first step', ru: 'первый шаг' })];
      for (const text of titles) {
        const th = document.createElement('th');
        th.textContent = text;
        head.append(th);
      }
      const body = table.createTBody();
      for (const row of rows) {
        const line = body.insertRow();
        line.insertCell().textContent = row.title || row.name;
        line.insertCell().textContent = n(counts.get(row.name));
        const cell = line.insertCell();
        const first = outline.firsts[`${byPhase ? 'phase' : 'type'}:${row.name}`];
        if (first) {
          const go = document.createElement('button');
          go.type = 'button';
          go.className = 'worked-example-step';
          go.dataset.step = String(first.step);
          go.textContent = n(first.step);
          go.title = tr({ en: `show step ${n(first.step)}`, ru: `показать шаг ${n(first.step)}` });
          go.addEventListener('click', () => goToStep(first.step));
          cell.append(go);
        } else {
          cell.textContent = '—';
        }
      }
      block.append(table);
    }
    const firstText = outline.runs.length ? firstStepText(outline) : '';
    if (firstText) {
      const p = document.createElement('p');
      p.textContent = tr({ en: `Step 1: ${firstText}`, ru: `Шаг 1: ${firstText}` });
      block.append(p);
    }
  }
}

function firstStepText(outline) {
  for (const first of Object.values(outline.firsts)) if (first.step === 1) return first.text;
  return '';
}
