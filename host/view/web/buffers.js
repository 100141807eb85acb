// The buffer viewer: a frame's per-pixel arrays (the `buffers` of /api/frame, and a step's own
// buffers such as z-pyramid levels) drawn in false colour with a legend; the hover readout of one
// pixel; and the pixel grid that prints each pixel's value in its cell. The page asks only for what
// it shows: a buffer view's one buffer over the whole picture, and every buffer over the tile of
// TILE × TILE pixels under the mouse for the readout.

import { typedArray } from './api.js';
import { tr } from './i18n.js';

export const BUFFER_NAMES = ['depth', 'face', 'instance', 'object', 'depth_tests', 'depth_complexity', 'scene_z'];
// The buffer each view shows.
export const VIEW_BUFFER = { 'depth': 'depth', 'depth-complexity': 'depth_complexity', 'depth-tests': 'depth_tests' };
export const TILE = 64;

// The tile of the readout around pixel (x, y): [x, y, width, height].
export function tileAround(x, y) {
  return [Math.floor(x / TILE) * TILE, Math.floor(y / TILE) * TILE, TILE, TILE];
}

export const EMPTY_ID = 4294967295;

// Viridis as a degree-6 polynomial (Matt Zucker's fit of matplotlib's colour map), t in [0, 1].
const VIRIDIS = [
  [0.2777273272234177, 0.005407344544966578, 0.3340998053353061],
  [0.1050930431085774, 1.404613529898575, 1.384590162594685],
  [-0.3308618287255563, 0.214847559468213, 0.09509516302823659],
  [-4.634230498983486, -5.799100973351585, -19.33244095627987],
  [6.228269936347081, 14.17993336680509, 56.69055260068105],
  [4.776384997670288, -13.74514537774601, -65.35303263337234],
  [-5.435455855934631, 4.645852612178535, 26.3124352495832],
];

export function viridis(t) {
  const x = Math.min(1, Math.max(0, t));
  return [0, 1, 2].map((channel) => {
    let v = 0;
    for (let i = VIRIDIS.length - 1; i >= 0; --i) v = v * x + VIRIDIS[i][channel];
    return Math.round(Math.min(1, Math.max(0, v)) * 255);
  });
}

const EMPTY_RGB = [24, 24, 30];

// The response's `buffers` (one answer or a list of them, each over its region): `whole` holds the
// arrays over the whole picture, `tiles` those over a part of it. Null when there are none.
export function decodeFrameBuffers(buffers, width, height) {
  const answers = Array.isArray(buffers) ? buffers : (buffers ? [buffers] : []);
  const decoded = { width, height, whole: {}, tiles: [] };
  for (const answer of answers) {
    const [x, y, w, h] = answer.region;
    const arrays = {
      depth: typedArray(answer.depth, Float32Array),
      face: typedArray(answer.face, Uint32Array),
      instance: typedArray(answer.instance, Uint32Array),
      object: typedArray(answer.object, Uint32Array),
      depthTests: typedArray(answer.depth_tests, Uint32Array),
      depthComplexity: typedArray(answer.depth_complexity, Uint32Array),
      sceneZ: typedArray(answer.scene_z, Float32Array),
    };
    if (x === 0 && y === 0 && w === width && h === height) {
      for (const [name, values] of Object.entries(arrays)) if (values) decoded.whole[name] = values;
    } else {
      decoded.tiles.push({ x, y, width: w, height: h, ...arrays });
    }
  }
  return answers.length ? decoded : null;
}

// A step's own buffers ({name, width, height, data}) decoded.
export function decodeStepBuffers(steps) {
  if (!steps || !Array.isArray(steps.buffers)) return [];
  return steps.buffers
    .map((b) => ({ name: b.name, width: b.width, height: b.height, values: typedArray(b.data, Float32Array) }))
    .filter((b) => b.values && b.values.length >= b.width * b.height);
}

function finiteRange(values) {
  let min = Infinity;
  let max = -Infinity;
  for (const v of values) {
    if (Number.isFinite(v) && v !== EMPTY_ID) {
      if (v < min) min = v;
      if (v > max) max = v;
    }
  }
  return min <= max ? { min, max } : null;
}

// Colours `values` (width*height) into ImageData; `nearIsHigh` flips the map so that small values
// (near depths) are bright. Returns {image, legend}.
function falseColour(values, width, height, { title, nearIsHigh, integer }) {
  const image = new ImageData(width, height);
  const range = integer ? { min: 0, max: Math.max(1, finiteRange(values)?.max ?? 1) } : finiteRange(values);
  const span = range ? range.max - range.min || 1 : 1;
  for (let i = 0; i < width * height; ++i) {
    const v = values[i];
    let rgb = EMPTY_RGB;
    if (range && Number.isFinite(v) && !(integer && v === 0)) {
      const t = (v - range.min) / span;
      rgb = viridis(nearIsHigh ? 1 - t : t);
    }
    image.data[i * 4] = rgb[0];
    image.data[i * 4 + 1] = rgb[1];
    image.data[i * 4 + 2] = rgb[2];
    image.data[i * 4 + 3] = 255;
  }
  return { image, legend: range ? { title, min: range.min, max: range.max, nearIsHigh, integer } : null };
}

// The picture of buffer view `view` ('depth', 'depth-complexity', 'depth-tests', 'step:<name>'),
// or null if the frame does not have that buffer.
export function bufferView(view, frameBuffers, stepBuffers) {
  if (view.startsWith('step:')) {
    const b = stepBuffers.find((s) => `step:${s.name}` === view);
    if (!b) return null;
    return { width: b.width, height: b.height,
      ...falseColour(b.values, b.width, b.height, { title: tr({ en: `${b.name} (near → far)`, ru: `${b.name} (ближе → дальше)` }), nearIsHigh: true }) };
  }
  if (!frameBuffers) return null;
  const { width, height, whole } = frameBuffers;
  const pick = {
    'depth': [whole.depth, { title: tr({ en: 'depth (near → far)', ru: 'глубина (ближе → дальше)' }), nearIsHigh: true }],
    'depth-complexity': [whole.depthComplexity, { title: tr({ en: 'surfaces over the pixel', ru: 'поверхностей в пикселе' }), integer: true }],
    'depth-tests': [whole.depthTests, { title: tr({ en: 'depth tests at the pixel', ru: 'тестов глубины в пикселе' }), integer: true }],
  }[view];
  if (!pick || !pick[0]) return null;
  return { width, height, ...falseColour(pick[0], width, height, pick[1]) };
}

const formatValue = (v, integer) => (integer ? String(Math.round(v)) : Number(v.toPrecision(6)).toString());

export function drawLegend(elements, legend) {
  elements.box.hidden = !legend;
  if (!legend) return;
  const ctx = elements.bar.getContext('2d');
  const w = elements.bar.width;
  for (let x = 0; x < w; ++x) {
    const t = x / (w - 1);
    const [r, g, b] = viridis(legend.nearIsHigh ? 1 - t : t);
    ctx.fillStyle = `rgb(${r},${g},${b})`;
    ctx.fillRect(x, 0, 1, elements.bar.height);
  }
  elements.min.textContent = formatValue(legend.min, legend.integer);
  elements.max.textContent = formatValue(legend.max, legend.integer);
  elements.title.textContent = legend.title;
}

const idText = (v) => (v === undefined || v === null || v === EMPTY_ID ? tr({ en: 'none', ru: 'нет' }) : String(v));

// Every buffer's value at pixel (x, y) from the tile that holds it, or null when no tile does.
function valuesAt(frameBuffers, x, y) {
  const tile = frameBuffers?.tiles.find((t) => t.depth && x >= t.x && y >= t.y && x < t.x + t.width && y < t.y + t.height);
  if (tile) {
    const i = (y - tile.y) * tile.width + (x - tile.x);
    return Object.fromEntries(Object.entries(tile).map(([name, values]) => [name, values?.[i]]));
  }
  const { whole } = frameBuffers || {};
  if (!whole || !whole.depth || !whole.face) return null;
  const i = y * frameBuffers.width + x;
  return Object.fromEntries(Object.entries(whole).map(([name, values]) => [name, values[i]]));
}

// "x, y: depth D, face F, object O, instance I" for pixel (x, y) (x from the left, y from the top),
// or null when the buffers shown do not cover it.
export function pixelInfo(frameBuffers, x, y) {
  const v = valuesAt(frameBuffers, x, y);
  if (!v) return null;
  if (!Number.isFinite(v.depth) && (v.face === undefined || v.face === EMPTY_ID)) {
    return tr({ en: `${x}, ${y}: empty (no surface), depth ∞`, ru: `${x}, ${y}: пусто (нет поверхности), глубина ∞` });
  }
  const [depth, face, object, instance] = [formatValue(v.depth), idText(v.face), idText(v.object), idText(v.instance)];
  let text = tr({
    en: `${x}, ${y}: depth ${depth}, face ${face}, object ${object}, instance ${instance}`,
    ru: `${x}, ${y}: глубина ${depth}, грань ${face}, объект ${object}, экземпляр ${instance}`,
  });
  if (Number.isFinite(v.sceneZ)) text += `, z ${formatValue(v.sceneZ)}`;
  if (v.depthComplexity !== undefined) text += tr({ en: `; ${v.depthComplexity} surfaces`, ru: `; поверхностей: ${v.depthComplexity}` });
  if (v.depthTests !== undefined) text += tr({ en: `, ${v.depthTests} depth tests`, ru: `, тестов глубины: ${v.depthTests}` });
  return text;
}

// The pixel grid as the textbook's table: one cell per pixel with its depth (mode 'depth') or its
// colour ('colour', r g b on three lines), the cell coloured like the picture. Depth is the scene's
// own z where the frame has it (a `camera pixel` scene: larger is nearer, nothing drawn is −∞), else
// the window depth (0 to 1, smaller is nearer, nothing drawn is ∞). The pixels the step shown wrote
// or rejected are outlined. Returns what the caption and the layout need: the label of the values,
// the marked cells' counts, and the longest text (characters per line, lines).
export function drawGrid(grid, { width, height, rgba, frameBuffers, mode, steps }) {
  const marks = new Map();
  for (const [x, y] of steps?.written || []) marks.set(y * width + x, 'written');
  for (const [x, y] of steps?.rejected || []) marks.set(y * width + x, 'rejected');
  const sceneZ = frameBuffers?.whole.sceneZ;
  const depth = frameBuffers?.whole.depth;
  const colour = mode === 'colour' || !(sceneZ || depth);
  grid.style.gridTemplateColumns = `repeat(${width}, var(--cell-width, 2.6rem))`;
  grid.classList.toggle('colour', colour);
  const cells = [];
  let longest = 1;
  let written = 0;
  let rejected = 0;
  for (let y = 0; y < height; ++y) {
    for (let x = 0; x < width; ++x) {
      const i = y * width + x;
      const r = rgba[i * 4];
      const g = rgba[i * 4 + 1];
      const b = rgba[i * 4 + 2];
      let text;
      if (colour) text = `${r}<br>${g}<br>${b}`;
      else if (sceneZ) text = Number.isFinite(sceneZ[i]) ? tableNumber(sceneZ[i]) : '−∞';
      else text = Number.isFinite(depth[i]) ? tableNumber(depth[i]) : '∞';
      if (!colour) longest = Math.max(longest, text.length);
      const dark = 0.299 * r + 0.587 * g + 0.114 * b < 128;
      const mark = marks.get(i);
      if (mark === 'written') written += 1;
      else if (mark === 'rejected') rejected += 1;
      const empty = text === '−∞' || text === '∞';
      cells.push(`<div class="cell${dark ? ' dark' : ''}${empty ? ' empty' : ''}${mark ? ` ${mark}` : ''}" `
        + `style="background:rgb(${r},${g},${b})" title="${x}, ${y}">${text}</div>`);
    }
  }
  grid.innerHTML = cells.join('');
  let label;
  if (colour) label = tr({ en: 'colour: red, green, blue (0–255)', ru: 'цвет: красный, зелёный, синий (0–255)' });
  else if (sceneZ) label = tr({ en: 'z (larger is nearer); −∞: no surface', ru: 'z (больше — ближе); −∞: поверхности нет' });
  else label = tr({ en: 'depth (smaller is nearer); ∞: no surface', ru: 'глубина (меньше — ближе); ∞: поверхности нет' });
  return {
    label, written, rejected, marked: Boolean(steps?.written || steps?.rejected),
    characters: colour ? 3 : longest, lines: colour ? 3 : 1,
  };
}

// A number as the table prints it: three significant digits, without trailing zeros.
function tableNumber(v) {
  return Number(v.toPrecision(3)).toString().replace(/^-/, '−');
}

// The size of the grid's cells and font for `columns` × `rows` cells of `characters` × `lines`
// characters in `room` ({width, height} px), the font at most `largest` px; null when the font
// would be smaller than `smallest` px. Monospaced digits are at most 0.62 em wide.
export function gridCells({ columns, rows, characters, lines, room, smallest, largest = 14 }) {
  const pad = 3;
  const lineHeight = 1.15;
  const byHeight = (room.height / rows - 1 - pad) / (lineHeight * lines);
  const byWidth = (room.width / columns - 1 - pad) / (0.62 * characters);
  const font = Math.floor(Math.min(largest, byHeight, byWidth) * 2) / 2;
  if (!(font >= smallest)) return null;
  return cellsOfFont(font, characters, lines);
}

export function cellsOfFont(font, characters, lines) {
  return {
    font,
    width: Math.ceil(0.62 * characters * font + 3),
    height: Math.ceil(1.15 * lines * font + 3),
  };
}
