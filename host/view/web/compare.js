// Compare: the same camera rendered by a second hidden-surface algorithm (/api/compare), shown
// beside the main picture with its stats and the diff image (b's picture dimmed, the pixels where
// the two visibility results differ in magenta) and the count of differing pixels.

import { numberText } from './i18n.js';
import { renderStats } from './stats.js';

export function compareRequest(frameRequest, algorithm) {
  const a = { ...frameRequest, step: null };
  const b = { ...a, algorithm, params: {} };
  return { a, b };
}

export function showCompare(el, response, names, roundTripMs) {
  for (const figure of el.figures) figure.hidden = false;
  el.statsB.hidden = false;
  el.imageB.src = response.b.png;
  el.diffImage.src = response.diff_png;
  el.captionA.textContent = names.a;
  el.captionB.textContent = names.b;
  el.diffCount.textContent = numberText(Number(response.differing_pixels));
  el.pictures.classList.add('comparing');
  renderStats(el.statsA, names.a, response.a.stats, roundTripMs);
  renderStats(el.statsB, names.b, response.b.stats, roundTripMs);
}

export function hideCompare(el) {
  for (const figure of el.figures) figure.hidden = true;
  el.statsB.hidden = true;
  el.captionA.textContent = '';
  el.diffCount.textContent = '–';
  el.pictures.classList.remove('comparing');
}
