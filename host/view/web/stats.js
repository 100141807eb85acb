// The stats panel: the current frame's timings and the algorithm's counters (as `hsr render --stats`).

const ms = (v) => (Number.isFinite(v) ? `${v.toFixed(1)} ms` : '–');

export function renderStats(element, title, stats, roundTripMs) {
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
    `visibility ${ms(stats.visibility_ms)}`, `shading ${ms(stats.shading_ms)}`,
    `PNG ${ms(stats.encode_ms)}`, `round trip ${ms(roundTripMs)}`,
  ].join(' · ');
  element.append(timings);
  const table = document.createElement('table');
  const rows = Object.entries(stats.counters || {});
  if (Number.isFinite(stats.triangles)) rows.unshift(['triangles', stats.triangles]);
  for (const [name, value] of rows) {
    const tr = table.insertRow();
    tr.insertCell().textContent = name;
    const cell = tr.insertCell();
    cell.textContent = typeof value === 'number' ? value.toLocaleString('en-US') : String(value);
    cell.className = 'number';
  }
  element.append(table);
}
