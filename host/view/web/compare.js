// Compare: the same camera rendered by a second algorithm of the same kind (/api/compare), shown
// beside the main picture with its stats and the diff image (b's picture dimmed, the pixels where
// the two visibility results differ in magenta: for two line drawings, the pixels that differ) and
// the count of differing pixels. Plugins of different kinds are not compared: a note says why.

import { numberText, tr } from './i18n.js';
import { renderStats } from './stats.js';

export function compareRequest(frameRequest, algorithm) {
  const a = { ...frameRequest, step: null };
  const b = { ...a, algorithm, params: {} };
  return { a, b };
}

// labels: {a, b}, each a counter name -> the label shown (stats.js counterLabels).
export function showCompare(el, response, names, roundTripMs, labels = {}) {
  for (const figure of el.figures) figure.hidden = false;
  el.statsB.hidden = false;
  el.imageB.src = response.b.png;
  el.diffImage.src = response.diff_png;
  el.captionA.textContent = names.a;
  el.captionB.textContent = names.b;
  el.diffCount.textContent = numberText(Number(response.differing_pixels));
  el.pictures.classList.add('comparing');
  renderStats(el.statsA, names.a, response.a.stats, roundTripMs, labels.a);
  renderStats(el.statsB, names.b, response.b.stats, roundTripMs, labels.b);
}

export function hideCompare(el) {
  for (const figure of el.figures) figure.hidden = true;
  el.statsB.hidden = true;
  el.captionA.textContent = '';
  el.diffCount.textContent = '–';
  el.pictures.classList.remove('comparing');
}

// The kind of the plugin named, as the server picks it: a hidden-surface plugin wins over a
// hidden-line one of the same name.
function drawsLines(plugins, name) {
  return !plugins.hidden_surface.some((p) => p.name === name) && plugins.hidden_line.some((p) => p.name === name);
}

// Why the two plugins cannot be compared, or null when they can.
export function compareMismatch(plugins, a, b) {
  const linesA = drawsLines(plugins, a), linesB = drawsLines(plugins, b);
  if (linesA === linesB) return null;
  const what = (name, lines) => (lines
    ? tr({ en: `${name} draws lines`, ru: `${name} рисует линии` })
    : tr({ en: `${name} fills surfaces`, ru: `${name} закрашивает поверхности` }));
  return tr({
    en: `Nothing to compare: ${what(a, linesA)}, ${what(b, linesB)}. Choose two hidden-surface plugins or two hidden-line plugins.`,
    ru: `Сравнивать нечего: ${what(a, linesA)}, а ${what(b, linesB)}. Выберите два алгоритма удаления невидимых поверхностей или два алгоритма удаления невидимых линий.`,
  });
}

// The note under the compare select: the message, or hidden when null.
export function showCompareNote(select, message) {
  let note = document.getElementById('compare-note');
  if (!note) {
    note = document.createElement('p');
    note.id = 'compare-note';
    note.className = 'compare-note';
    note.setAttribute('role', 'status');
    select.insertAdjacentElement('afterend', note);
  }
  note.hidden = !message;
  note.textContent = message || '';
}
