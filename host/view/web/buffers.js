// The buffer viewer: a frame's per-pixel arrays (the `buffers` of /api/frame, and a step's own
// buffers such as z-pyramid levels) decoded from base64 and drawn in false colour with a legend;
// the hover readout of one pixel; and the pixel grid that prints each pixel's value in its cell.

import { decodeArray } from './api.js';

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

// The response's `buffers` as typed arrays (each width*height), or null.
export function decodeFrameBuffers(buffers, width, height) {
  if (!buffers) return null;
  const decoded = {
    width, height,
    depth: decodeArray(buffers.depth, Float32Array),
    face: decodeArray(buffers.face, Uint32Array),
    instance: decodeArray(buffers.instance, Uint32Array),
    object: decodeArray(buffers.object, Uint32Array),
    depthTests: decodeArray(buffers.depth_tests, Uint32Array),
    depthComplexity: decodeArray(buffers.depth_complexity, Uint32Array),
  };
  return decoded.depth && decoded.depth.length >= width * height ? decoded : null;
}

// A step's own buffers ({name, width, height, data}) decoded.
export function decodeStepBuffers(steps) {
  if (!steps || !Array.isArray(steps.buffers)) return [];
  return steps.buffers
    .map((b) => ({ name: b.name, width: b.width, height: b.height, values: decodeArray(b.data, Float32Array) }))
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
      ...falseColour(b.values, b.width, b.height, { title: `${b.name} (near → far)`, nearIsHigh: true }) };
  }
  if (!frameBuffers) return null;
  const { width, height } = frameBuffers;
  const pick = {
    'depth': [frameBuffers.depth, { title: 'depth (near → far)', nearIsHigh: true }],
    'depth-complexity': [frameBuffers.depthComplexity, { title: 'surfaces over the pixel', integer: true }],
    'depth-tests': [frameBuffers.depthTests, { title: 'depth tests at the pixel', integer: true }],
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

const idText = (v) => (v === undefined || v === null || v === EMPTY_ID ? 'none' : String(v));

// "x, y: depth D, face F, object O, instance I" for pixel (x, y) (x from the left, y from the top).
export function pixelInfo(frameBuffers, x, y) {
  const i = y * frameBuffers.width + x;
  const depth = frameBuffers.depth[i];
  const face = frameBuffers.face?.[i];
  if (!Number.isFinite(depth) && (face === undefined || face === EMPTY_ID)) {
    return `${x}, ${y}: empty (no surface), depth ∞`;
  }
  let text = `${x}, ${y}: depth ${formatValue(depth)}, face ${idText(face)}, object ${idText(frameBuffers.object?.[i])}, `
    + `instance ${idText(frameBuffers.instance?.[i])}`;
  if (frameBuffers.depthComplexity) text += `; ${frameBuffers.depthComplexity[i]} surfaces`;
  if (frameBuffers.depthTests) text += `, ${frameBuffers.depthTests[i]} depth tests`;
  return text;
}

// The pixel grid: one cell per pixel with its depth (mode 'depth') or colour ('colour'), the cell
// coloured like the picture; the pixels a step wrote or rejected are outlined.
export function drawGrid(grid, { width, height, rgba, frameBuffers, mode, steps }) {
  const marks = new Map();
  for (const [x, y] of steps?.written || []) marks.set(y * width + x, 'written');
  for (const [x, y] of steps?.rejected || []) marks.set(y * width + x, 'rejected');
  grid.style.gridTemplateColumns = `repeat(${width}, var(--cell))`;
  const cells = [];
  for (let y = 0; y < height; ++y) {
    for (let x = 0; x < width; ++x) {
      const i = y * width + x;
      const r = rgba[i * 4];
      const g = rgba[i * 4 + 1];
      const b = rgba[i * 4 + 2];
      let text;
      if (mode === 'colour' || !frameBuffers) text = `${r},${g},${b}`;
      else {
        const d = frameBuffers.depth[i];
        text = Number.isFinite(d) ? Number(d.toPrecision(3)).toString() : '·';
      }
      const dark = 0.299 * r + 0.587 * g + 0.114 * b < 128;
      const mark = marks.get(i);
      cells.push(`<div class="cell${dark ? ' dark' : ''}${mark ? ` ${mark}` : ''}" `
        + `style="background:rgb(${r},${g},${b})" title="${x}, ${y}">${text}</div>`);
    }
  }
  grid.innerHTML = cells.join('');
}
