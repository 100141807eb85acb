// The stats panel: the current frame's timings and the algorithm's counters (as `hsr render --stats`).

import { tr, numberText, pluginText } from './i18n.js';

// What the host counts for every plugin, as `hsr render --stats` names it; each row keeps that
// name as its title. A plugin's translation of a counter of the same name (weiler-atherton counts
// its own "fragments") comes first.
const HOST_COUNTERS = {
  'triangles': { en: 'triangles', ru: 'треугольники' },
  'fragments-shaded': { en: 'fragments-shaded', ru: 'закрашенные фрагменты' },
  'shading-batches': { en: 'shading-batches', ru: 'пакеты закраски' },
  'fragments': { en: 'fragments', ru: 'фрагменты' },
  'edges-requested': { en: 'edges-requested', ru: 'рёбра на входе' },
};

const ms = (v) => (Number.isFinite(v) ? tr({ en: `${v.toFixed(1)} ms`, ru: `${v.toFixed(1).replace('.', ',')} мс` }) : '–');

// A counter's label in the page's language, from the first of `plugins` (/api/plugins entries) that
// translates it; else its name. The name stays on hover, as `hsr render --stats` prints it.
export function counterLabels(plugins) {
  return (name) => {
    for (const plugin of plugins) {
      const text = pluginText(plugin, `counter:${name}`, null);
      if (text) return text;
    }
    return name;
  };
}

export function renderStats(element, title, stats, roundTripMs, counterLabel = (name) => name) {
  element.replaceChildren();
  if (title) {
    const h = document.createElement('h3');
    h.textContent = title;
    element.append(h);
  }
  if (!stats) return;
  const timings = document.createElement('p');
  timings.className = 'timings';
  timings.textContent = [
    tr({ en: `visibility ${ms(stats.visibility_ms)}`, ru: `видимость ${ms(stats.visibility_ms)}` }),
    tr({ en: `shading ${ms(stats.shading_ms)}`, ru: `закраска ${ms(stats.shading_ms)}` }),
    tr({ en: `PNG ${ms(stats.encode_ms)}`, ru: `PNG ${ms(stats.encode_ms)}` }),
    tr({ en: `round trip ${ms(roundTripMs)}`, ru: `запрос и ответ ${ms(roundTripMs)}` }),
  ].join(' · ');
  element.append(timings);
  const table = document.createElement('table');
  const rows = Object.entries(stats.counters || {});
  if (Number.isFinite(stats.triangles)) rows.unshift(['triangles', stats.triangles]);
  for (const [name, value] of rows) {
    const row = table.insertRow();
    const label = row.insertCell();
    const pluginLabel = counterLabel(name);
    label.textContent = pluginLabel !== name || !HOST_COUNTERS[name] ? pluginLabel : tr(HOST_COUNTERS[name]);
    if (label.textContent !== name) label.title = name;
    const cell = row.insertCell();
    cell.textContent = typeof value === 'number' ? numberText(value) : String(value);
    cell.className = 'number';
  }
  element.append(table);
}
