// The camera: orbit (yaw, pitch, zoom: drag and wheel on the picture) or look-at (eye, target, up),
// perspective or orthographic. Angles move in half degrees and zoom keeps three decimals, so that
// every view the page shows is one `hsr render --yaw --pitch --zoom` reproduces exactly.

import { tr } from './i18n.js';

export const DEFAULT_CAMERA = Object.freeze({
  yaw: 30, pitch: 20, zoom: 1, projection: 'perspective', fov: 35, eye: '', target: '', up: '',
});

const DEGREES_PER_PIXEL = 0.5;
const ZOOM_PER_WHEEL_NOTCH = 1.1;

// "x,y,z" -> [x, y, z]; '' -> null; anything else -> undefined (invalid).
export function parseVector(text) {
  const t = String(text || '').trim();
  if (t === '') return null;
  const parts = t.split(/[\s,]+/).map(Number);
  if (parts.length !== 3 || parts.some((v) => !Number.isFinite(v))) return undefined;
  return parts;
}

function wrapDegrees(angle) {
  let a = angle % 360;
  if (a > 180) a -= 360;
  if (a <= -180) a += 360;
  return a;
}

const roundTo = (value, step) => Math.round(value / step) * step;

export class Camera {
  // inputs: {projection, yaw, pitch, zoom, fov, eye, target, up} elements; onChange() after any change.
  constructor(inputs, onChange) {
    this.inputs = inputs;
    this.onChange = onChange;
    this.state = { ...DEFAULT_CAMERA };
    this.dragging = false;
    this.onDragEnd = null;
    for (const key of Object.keys(inputs)) {
      inputs[key].addEventListener('change', () => this.readInputs());
    }
  }

  set(state) {
    this.state = { ...DEFAULT_CAMERA, ...(state && typeof state === 'object' ? state : {}) };
    for (const key of Object.keys(DEFAULT_CAMERA)) {
      if (typeof this.state[key] !== typeof DEFAULT_CAMERA[key]) this.state[key] = DEFAULT_CAMERA[key];
    }
    this.writeInputs();
  }

  reset() {
    this.set(DEFAULT_CAMERA);
    this.onChange();
  }

  writeInputs() {
    const s = this.state;
    for (const key of Object.keys(this.inputs)) this.inputs[key].value = String(s[key]);
  }

  readInputs() {
    const s = { ...this.state };
    for (const key of ['yaw', 'pitch', 'zoom', 'fov']) {
      const v = Number(this.inputs[key].value);
      if (Number.isFinite(v)) s[key] = v;
    }
    s.pitch = Math.max(-89, Math.min(89, s.pitch));
    if (!(s.zoom > 0)) s.zoom = this.state.zoom;
    s.projection = this.inputs.projection.value;
    for (const key of ['eye', 'target', 'up']) s[key] = this.inputs[key].value.trim();
    this.state = s;
    this.writeInputs();
    this.onChange();
  }

  // Orbit by a drag of (dx, dy) CSS pixels. A look-at camera has no yaw and pitch, so a drag
  // goes back to orbiting.
  orbit(dx, dy) {
    const s = this.state;
    s.yaw = wrapDegrees(s.yaw + dx * DEGREES_PER_PIXEL);
    s.pitch = Math.max(-89, Math.min(89, s.pitch + dy * DEGREES_PER_PIXEL));
    s.eye = '';
    this.writeInputs();
    this.onChange();
  }

  zoomBy(notches) {
    const s = this.state;
    s.zoom = Math.max(0.01, Math.min(1000, roundTo(s.zoom * ZOOM_PER_WHEEL_NOTCH ** notches, 0.001)));
    s.zoom = Number(s.zoom.toFixed(3));
    this.writeInputs();
    this.onChange();
  }

  // Drag = orbit, wheel = zoom, on the given element.
  attach(element) {
    let last = null;
    element.addEventListener('pointerdown', (e) => {
      if (e.button !== 0) return;
      last = { x: e.clientX, y: e.clientY };
      element.setPointerCapture(e.pointerId);
      element.classList.add('dragging');
      this.dragging = true;
    });
    element.addEventListener('pointermove', (e) => {
      if (!last) return;
      const dx = Math.round(e.clientX - last.x);
      const dy = Math.round(e.clientY - last.y);
      if (dx === 0 && dy === 0) return;
      last = { x: last.x + dx, y: last.y + dy };
      this.orbit(dx, dy);
    });
    const end = () => {
      last = null;
      element.classList.remove('dragging');
      this.dragging = false;
      this.onDragEnd?.();
    };
    element.addEventListener('pointerup', end);
    element.addEventListener('pointercancel', end);
    element.addEventListener('wheel', (e) => {
      e.preventDefault();
      this.zoomBy(e.deltaY < 0 ? 1 : -1);
    }, { passive: false });
  }

  // The `camera` object of a frame request, or throws with a message naming the bad input.
  request() {
    const s = this.state;
    const camera = {
      yaw: s.yaw, pitch: s.pitch, zoom: s.zoom, projection: s.projection, fov: s.fov,
      eye: null, target: null, up: null,
    };
    for (const key of ['eye', 'target', 'up']) {
      const v = parseVector(s[key]);
      if (v === undefined) {
        const name = tr({ en: key, ru: { eye: 'глаз', target: 'цель', up: 'верх' }[key] });
        throw Object.assign(new Error(tr({ en: `${name}: expected x,y,z`, ru: `${name}: ожидается x,y,z` })), { field: `camera.${key}` });
      }
      camera[key] = v;
    }
    return camera;
  }
}

// The `hsr render` options of a request's camera.
export function cliCameraOptions(camera) {
  const options = [];
  if (camera.eye) {
    options.push(`--eye ${camera.eye.join(',')}`);
    if (camera.target) options.push(`--target ${camera.target.join(',')}`);
    if (camera.up) options.push(`--up ${camera.up.join(',')}`);
  } else {
    options.push(`--yaw ${camera.yaw}`, `--pitch ${camera.pitch}`);
  }
  options.push(`--zoom ${camera.zoom}`);
  if (camera.projection === 'orthographic') options.push('--ortho');
  if (camera.fov !== 35) options.push(`--fov ${camera.fov}`);
  return options;
}
