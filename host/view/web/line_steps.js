// One step of a hidden-line plugin over the picture, drawn so that it shows what hides what: the
// edge under test thick and labelled, the face the step names filled (its polygon, from the
// server's "figure"), visible pieces solid, hidden ones dashed, the lines the step works with
// (Appel: the contour line crossed; Roberts: the hiding body's edges), and on request every
// edge's and face's number. Beside the step bar, a key in the algorithm's own words.

import { tr, onLanguageChange } from './i18n.js';

// Role colours for a light picture and for a dark one, each at least 4.5:1 against it.
const PALETTES = {
  light: { edge: '#b04a00', visible: '#1a7f37', hidden: '#c62828', context: '#0b5cad', face: '#7b1fa2',
    label: '#1d2330', halo: '#ffffff' },
  dark: { edge: '#ff9f43', visible: '#4ade80', hidden: '#ff7b7b', context: '#5cc8ff', face: '#d8a6ff',
    label: '#f4f5f7', halo: '#15171c' },
};
const LABELS_SETTING = 'hsr-view-line-labels';

// The keys of each algorithm's legend, in its own words; `kind` picks the swatch's style.
const KEYS = {
  appel: [
    { kind: 'edge', text: { en: 'edge under test', ru: 'проверяемое ребро' } },
    { kind: 'context', text: { en: 'contour line crossed', ru: 'пересекаемая контурная линия' } },
    { kind: 'visible', text: { en: 'visible part, QI = 0', ru: 'видимая часть, КН = 0' } },
    { kind: 'hidden', text: { en: 'hidden part, QI > 0', ru: 'невидимая часть, КН > 0' } },
    { kind: 'face', text: { en: 'face of the contour', ru: 'грань контура' } },
  ],
  roberts: [
    { kind: 'edge', text: { en: 'edge under test', ru: 'проверяемое ребро' } },
    { kind: 'face', text: { en: 'hiding face', ru: 'закрывающая грань' } },
    { kind: 'context', text: { en: 'edges of the hiding body', ru: 'рёбра закрывающего тела' } },
    { kind: 'hidden', text: { en: 'hidden interval t0..t1', ru: 'закрытый участок t0..t1' } },
    { kind: 'visible', text: { en: 'visible part', ru: 'видимая часть' } },
  ],
  other: [
    { kind: 'edge', text: { en: 'line under test', ru: 'проверяемая линия' } },
    { kind: 'visible', text: { en: 'visible part', ru: 'видимая часть' } },
    { kind: 'hidden', text: { en: 'hidden part', ru: 'невидимая часть' } },
    { kind: 'context', text: { en: 'what the step works with', ru: 'с чем работает шаг' } },
  ],
};
const NOTES = {
  appel: {
    en: 'QI, quantitative invisibility: how many faces lie between a point of the edge and the eye. It changes only where the edge passes behind a contour line (or through a face); the pieces with QI 0 are drawn.',
    ru: 'КН — количественная невидимость: сколько граней лежит между точкой ребра и глазом. Она меняется только там, где ребро проходит за контурной линией (или сквозь грань); рисуются участки с КН = 0.',
  },
  roberts: {
    en: 't runs along the edge from 0 at its first end to 1 at its second; t0..t1 is the part of it that a body hides. Each convex body hides at most one interval of an edge.',
    ru: 'Параметр t пробегает ребро от 0 в его начале до 1 в конце; t0..t1 — участок, который закрывает тело. Выпуклое тело закрывает не более одного участка ребра.',
  },
  other: { en: '', ru: '' },
};
const NUMBERS_NOTE = { en: '12: edge number, [28]: face number', ru: '12 — номер ребра, [28] — номер грани' };

let last = null;  // { canvas, steps }: redrawn when the labels box or the language changes

// Is this a hidden-line plugin's step (the server sends its figure)?
export function isLineStep(steps) {
  return Boolean(steps && steps.figure);
}

// The colours for a picture of background [r, g, b] (0-255).
export function lineStepPalette(background) {
  const [r, g, b] = Array.isArray(background) ? background : [255, 255, 255];
  const luminance = (0.2126 * r + 0.7152 * g + 0.0722 * b) / 255;
  return luminance >= 0.5 ? PALETTES.light : PALETTES.dark;
}

function labelsWanted() {
  try {
    return localStorage.getItem(LABELS_SETTING) === 'on';
  } catch {
    return false;
  }
}

// Draws the step on the overlay canvas (already cleared).
export function drawLineStep(canvas, steps) {
  last = { canvas, steps };
  const ctx = canvas.getContext('2d');
  const figure = steps.figure;
  const colors = lineStepPalette(figure.background);
  canvas.dataset.lineStep = figure.algorithm || '';
  // Widths in display pixels, whatever the picture's scale on screen.
  const scale = canvas.width / Math.max(1, canvas.getBoundingClientRect().width || canvas.width);
  const lines = Array.isArray(steps.lines) ? steps.lines : [];
  const stroke = (segments, color, width, dash = []) => {
    ctx.strokeStyle = color;
    ctx.lineWidth = width * scale;
    ctx.setLineDash(dash.map((d) => d * scale));
    ctx.beginPath();
    for (const [x0, y0, x1, y1] of segments) {
      ctx.moveTo(x0, y0);
      ctx.lineTo(x1, y1);
    }
    ctx.stroke();
    ctx.setLineDash([]);
  };
  const ofRole = (role) => lines.filter((line) => line[4] === role);
  ctx.lineCap = 'round';
  ctx.lineJoin = 'round';

  if (figure.face) {
    ctx.beginPath();
    for (const loop of figure.face.loops) {
      loop.forEach(([x, y], k) => (k === 0 ? ctx.moveTo(x, y) : ctx.lineTo(x, y)));
      ctx.closePath();
    }
    ctx.globalAlpha = 0.22;
    ctx.fillStyle = colors.face;
    ctx.fill('evenodd');
    ctx.globalAlpha = 1;
    ctx.strokeStyle = colors.face;
    ctx.lineWidth = 2 * scale;
    ctx.stroke();
  }
  stroke(ofRole(3), colors.context, 2);
  // The edge under test: the whole of it as a wide band and a line along its middle, under its
  // pieces, which stand out from the band by colour and dashes.
  const edgeLines = figure.edge ? [...figure.edge.lines, ...ofRole(0)] : ofRole(0);
  ctx.globalAlpha = 0.35;
  stroke(edgeLines, colors.edge, 11);
  ctx.globalAlpha = 1;
  stroke(edgeLines, colors.edge, 2.5);
  ctx.lineCap = 'butt';
  stroke(ofRole(1), colors.visible, 4);
  stroke(ofRole(2), colors.hidden, 4, [7, 5]);

  const text = (words, x, y, color, size) => {
    ctx.font = `600 ${size * scale}px system-ui, sans-serif`;
    ctx.textAlign = 'center';
    ctx.textBaseline = 'middle';
    ctx.lineWidth = 3 * scale;
    ctx.strokeStyle = colors.halo;
    ctx.strokeText(words, x, y);
    ctx.fillStyle = color;
    ctx.fillText(words, x, y);
  };
  if (labelsWanted() && figure.labels) {
    for (const [index, x, y] of figure.labels.faces) text(`[${index}]`, x, y, colors.face, 11);
    for (const [index, x, y] of figure.labels.edges) text(String(index), x, y, colors.label, 11);
  }
  if (figure.face) {
    const [x, y] = figure.face.label;
    text(tr({ en: `face ${figure.face.index}`, ru: `грань ${figure.face.index}` }), x, y, colors.face, 13);
  }
  if (figure.edge) {
    // The label beside the edge's middle, off the line.
    const [x0, y0, x1, y1] = figure.edge.lines[0];
    const length = Math.hypot(x1 - x0, y1 - y0) || 1;
    const off = 14 * scale;
    const [x, y] = figure.edge.label;
    text(tr({ en: `edge ${figure.edge.index}`, ru: `ребро ${figure.edge.index}` }),
      x - ((y1 - y0) / length) * off, y + ((x1 - x0) / length) * off, colors.edge, 13);
  }
}

// The key below the step buttons: the algorithm's own for a hidden-line step, the general one
// (subject, written, ...) otherwise. Made on first use, inside #steps.
export function showLineStepKey(steps) {
  const general = document.querySelector('#steps .step-key');
  let key = document.getElementById('line-step-key');
  const shown = isLineStep(steps);
  if (!shown) {
    if (key) key.hidden = true;
    if (general) general.style.display = '';
    last = null;
    return;
  }
  if (!key) key = makeKey(general);
  if (general) general.style.display = 'none';
  key.hidden = false;
  fillKey(key, steps.figure);
}

function makeKey(general) {
  const key = document.createElement('div');
  key.id = 'line-step-key';
  key.className = 'line-step-key';
  const container = document.getElementById('steps');
  if (general) general.after(key);
  else container?.append(key);
  return key;
}

function fillKey(key, figure) {
  const algorithm = KEYS[figure.algorithm] ? figure.algorithm : 'other';
  const colors = lineStepPalette(figure.background);
  key.dataset.algorithm = algorithm;
  key.setAttribute('aria-label', tr({ en: 'legend', ru: 'условные обозначения' }));
  key.replaceChildren();
  const items = document.createElement('div');
  items.className = 'line-keys';
  for (const { kind, text } of KEYS[algorithm]) {
    const item = document.createElement('span');
    item.className = `line-key ${kind}`;
    const swatch = document.createElement('span');
    swatch.className = 'swatch';
    swatch.dataset.kind = kind;
    swatch.style.setProperty('--swatch', colors[kind]);
    item.append(swatch, tr(text));
    items.append(item);
  }
  const numbers = document.createElement('label');
  numbers.className = 'line-numbers';
  const box = document.createElement('input');
  box.type = 'checkbox';
  box.id = 'line-labels';
  box.checked = labelsWanted();
  box.addEventListener('change', () => {
    try {
      localStorage.setItem(LABELS_SETTING, box.checked ? 'on' : 'off');
    } catch { /* settings are not kept */ }
    redraw();
  });
  numbers.append(box, tr({ en: 'face and edge numbers', ru: 'номера граней и рёбер' }));
  items.append(numbers);
  key.append(items);
  const note = document.createElement('p');
  note.className = 'line-note';
  note.textContent = [tr(NOTES[algorithm]), box.checked ? tr(NUMBERS_NOTE) : ''].filter(Boolean).join(' ');
  key.append(note);
}

function redraw() {
  if (!last) return;
  const { canvas, steps } = last;
  canvas.getContext('2d').clearRect(0, 0, canvas.width, canvas.height);
  drawLineStep(canvas, steps);
  showLineStepKey(steps);
}

onLanguageChange(redraw);
