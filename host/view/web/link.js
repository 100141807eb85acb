// The page's state in the URL's hash, so that a link opens the same step of the same picture:
//   #model=1/zbuffer-exercise.scene&algorithm=zbuffer&p.tiles=4&lighting=blinn-phong&l.ambient=0.1
//    &yaw=30&pitch=20&zoom=1&projection=perspective&fov=35&eye=&target=&up=&width=32&height=32
//    &step=5&view=depth&grid=depth&theory=1&compare=painter
// `p.NAME` are the algorithm's parameters, `l.NAME` the lighting's. The hash never reaches the
// server. readLink() checks each value's form and lists the keys it ignored; what must be one of
// the server's lists (models, plugins) app.js checks.

import { DEFAULT_CAMERA } from './camera.js';

const VIEWS = ['frame', 'depth', 'depth-complexity', 'depth-tests'];
const GRID_MODES = ['depth', 'colour', 'off'];
const KNOWN = ['model', 'algorithm', 'lighting', 'width', 'height', 'step', 'view', 'grid', 'theory', 'compare',
  ...Object.keys(DEFAULT_CAMERA)];

// The hash of `state`: {model, algorithm, params, lighting, lightingParams, camera, width, height,
// step, view, grid, theory, compare}, null and empty parts left out but for the camera's.
export function linkHash(state) {
  const q = new URLSearchParams();
  const put = (key, value) => {
    if (value !== null && value !== undefined && value !== '') q.set(key, String(value));
  };
  put('model', state.model);
  put('algorithm', state.algorithm);
  for (const [k, v] of Object.entries(state.params || {})) put(`p.${k}`, v);
  put('lighting', state.lighting);
  for (const [k, v] of Object.entries(state.lightingParams || {})) put(`l.${k}`, v);
  for (const key of Object.keys(DEFAULT_CAMERA)) {
    const value = state.camera?.[key];
    if (value !== undefined && value !== null) q.set(key, String(value));
  }
  put('width', state.width);
  put('height', state.height);
  put('step', state.step);
  put('view', state.view);
  put('grid', state.grid);
  if (state.theory) q.set('theory', '1');
  put('compare', state.compare);
  return `#${q.toString().replace(/%2F/gi, '/').replace(/%2C/gi, ',')}`;
}

const wholeNumber = (text, min, max) => {
  const n = Number(text);
  return /^\d+$/.test(text) && n >= min && n <= max ? n : undefined;
};

// The state a hash gives: only the keys it holds, each of the right form; `bad` lists the keys
// whose values are not (and keys the page does not know). Null for an empty hash.
export function readLink(hash, { maxImageSide = 4096 } = {}) {
  const text = String(hash || '').replace(/^#/, '');
  if (!text) return null;
  let q;
  try {
    q = new URLSearchParams(text);
  } catch {
    return { state: {}, bad: ['#'] };
  }
  const state = {};
  const bad = [];
  const camera = {};
  for (const [key, value] of q) {
    if (key.startsWith('p.') && key.length > 2) {
      (state.params ??= {})[key.slice(2)] = value;
    } else if (key.startsWith('l.') && key.length > 2) {
      (state.lightingParams ??= {})[key.slice(2)] = value;
    } else if (key in DEFAULT_CAMERA) {
      if (typeof DEFAULT_CAMERA[key] === 'number') {
        const n = Number(value);
        if (value.trim() !== '' && Number.isFinite(n) && (key !== 'zoom' || n > 0) && (key !== 'fov' || (n >= 1 && n <= 179))
          && (key !== 'pitch' || Math.abs(n) <= 89)) camera[key] = n;
        else bad.push(key);
      } else if (key === 'projection') {
        if (value === 'perspective' || value === 'orthographic') camera[key] = value;
        else bad.push(key);
      } else if (value === '' || /^\s*-?[\d.e+-]+\s*,\s*-?[\d.e+-]+\s*,\s*-?[\d.e+-]+\s*$/i.test(value)) {
        camera[key] = value;
      } else {
        bad.push(key);
      }
    } else if (key === 'width' || key === 'height') {
      const n = wholeNumber(value, 1, maxImageSide);
      if (n === undefined) bad.push(key);
      else state[key] = n;
    } else if (key === 'step') {
      const n = wholeNumber(value, 1, Number.MAX_SAFE_INTEGER);
      if (n === undefined) bad.push(key);
      else state.step = n;
    } else if (key === 'view') {
      if (VIEWS.includes(value) || /^step:[\w.-]+$/.test(value)) state.view = value;
      else bad.push(key);
    } else if (key === 'grid') {
      if (GRID_MODES.includes(value)) state.grid = value;
      else bad.push(key);
    } else if (key === 'theory') {
      if (value === '1' || value === '0') state.theory = value === '1';
      else bad.push(key);
    } else if (KNOWN.includes(key)) {
      if (value) state[key] = value;
      else bad.push(key);
    } else {
      bad.push(key);
    }
  }
  if (Object.keys(camera).length) state.camera = camera;
  return { state, bad };
}
