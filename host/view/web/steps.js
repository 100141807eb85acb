// Step-by-step controls (play/pause, back/forward, first/last, slider, number box, speed) and the
// overlay that draws what one step did over the picture: its lines coloured by role (hsr_step_role:
// subject, written, rejected, context), its triangle's outline, and the pixels it wrote or rejected.

import { tr } from './i18n.js';
import { drawLineStep, isLineStep, showLineStepKey } from './line_steps.js';

export const ROLE_COLORS = ['#ffd400', '#34d058', '#ff4d4f', '#2fd3ff'];  // subject written rejected context
const OUTLINE_COLOR = '#ffffff';
const PLAY_ICON = '<svg viewBox="0 0 16 16" width="14" height="14" aria-hidden="true"><path d="M4 3v10l9-5z" fill="currentColor"/></svg>';
const PAUSE_ICON = '<svg viewBox="0 0 16 16" width="14" height="14" aria-hidden="true">'
  + '<rect x="3.5" y="3" width="3" height="10" fill="currentColor"/><rect x="9.5" y="3" width="3" height="10" fill="currentColor"/></svg>';

export class StepControls {
  // el: the controls by id; onStep(k) asks for step k (null = the full render).
  constructor(el, onStep) {
    this.el = el;
    this.onStep = onStep;
    this.total = null;       // steps of the full render, once the server told
    this.current = null;     // the step shown or asked for, null = the full render
    this.shownStep = null;   // the step of the picture on screen, null = the full render
    this.playing = false;
    this.timer = null;
    this.lastAdvance = 0;
    // Set by the outline (outline.js): mover(k, dir) gives the step one coarse unit from k, null
    // when there is none, undefined when the unit is one step; onShown() follows every change of
    // the step shown.
    this.mover = null;
    this.onShown = null;

    el.first.addEventListener('click', () => this.go(1));
    el.last.addEventListener('click', () => this.go(this.total ?? null));
    el.back.addEventListener('click', () => this.go(Math.max(1, (this.current ?? this.total ?? 2) - 1)));
    el.forward.addEventListener('click', () => this.go(this.current === null ? 1 : this.current + 1));
    el.play.addEventListener('click', () => this.setPlaying(!this.playing));
    el.slider.addEventListener('input', () => this.go(Number(el.slider.value)));
    // The keys step wherever the focus is but in a field that takes typing: space plays and pauses,
    // the arrows step back and forward, Home and End go to the first and last step. They are taken
    // in the capture phase, before a focused select or checkbox acts on them.
    window.addEventListener('keydown', (e) => this.key(e), true);
    el.number.addEventListener('change', () => {
      const k = Math.round(Number(el.number.value));
      if (Number.isFinite(k) && k >= 1) this.go(k);
    });
  }

  speed() {
    return Number(this.el.speed.value) || 1;
  }

  key(e) {
    if (e.ctrlKey || e.altKey || e.metaKey || e.isComposing || this.el.play.closest('[hidden]')) return;
    if (typesText(e.target)) return;
    const el = this.el;
    if (e.key === ' ') this.setPlaying(!this.playing);
    else if (e.shiftKey && (e.key === 'ArrowRight' || e.key === 'ArrowLeft')) this.byUnit(e.key === 'ArrowRight' ? 1 : -1);
    else if (e.key === 'ArrowRight') el.forward.click();
    else if (e.key === 'ArrowLeft') el.back.click();
    else if (e.key === 'Home') el.first.click();
    else if (e.key === 'End') el.last.click();
    else return;
    e.preventDefault();
    e.stopPropagation();
  }

  // One step of the chosen coarse unit forward (1) or back (-1); where there is none, nothing.
  byUnit(dir) {
    const k = this.mover ? this.mover(this.current, dir) : undefined;
    if (k === undefined) (dir > 0 ? this.el.forward : this.el.back).click();
    else if (k !== null) this.go(k);
  }

  // Step k (clamped to the known total), or the full render for null.
  go(k) {
    if (k !== null) {
      k = Math.max(1, Math.round(k));
      if (this.total !== null) k = Math.min(k, this.total);
    }
    this.current = k;
    this.show();
    this.onStep(k);
  }

  setPlaying(playing) {
    this.playing = playing;
    this.el.play.innerHTML = playing ? PAUSE_ICON : PLAY_ICON;
    this.el.play.setAttribute('aria-label', playLabel(playing));
    this.el.play.classList.toggle('active', playing);
    if (playing) {
      if (this.current === null || (this.total !== null && this.current >= this.total)) this.current = 0;
      this.lastAdvance = performance.now();
      this.advance();
    } else {
      clearTimeout(this.timer);
      this.timer = null;
    }
  }

  // One tick of playback: as many steps as the speed asks for in the time since the last tick
  // (a render may take longer than a step at high speed), then wait for that frame.
  advance() {
    if (!this.playing) return;
    const now = performance.now();
    const due = Math.max(1, Math.round(((now - this.lastAdvance) / 1000) * this.speed()));
    this.lastAdvance = now;
    // Playing by a coarse unit moves one unit a tick.
    const coarse = this.mover ? this.mover(this.current ?? 0, 1) : undefined;
    const next = coarse === undefined ? (this.current ?? 0) + due : (coarse ?? this.total ?? 0);
    if (this.total !== null && next >= this.total) {
      this.go(this.total);
      this.setPlaying(false);
      return;
    }
    this.go(next);
  }

  // Called with each frame the page shows (its `steps` field, or null).
  frameShown(steps, isStepRequest) {
    if (steps && Number.isFinite(steps.total)) this.total = steps.total;
    if (steps && isStepRequest && Number.isFinite(steps.current)) this.current = steps.current;
    this.shownStep = isStepRequest ? this.current : null;
    this.el.text.textContent = steps && isStepRequest && steps.text ? stepText(steps.current, steps.text) : fullRenderText(this.total);
    this.show();
    if (this.playing) {
      const wait = Math.max(0, 1000 / this.speed() - (performance.now() - this.lastAdvance));
      clearTimeout(this.timer);
      this.timer = setTimeout(() => this.advance(), wait);
    }
  }

  // The step count of the full render shown, learnt before any step is asked for.
  setTotal(total) {
    this.total = total;
    if (this.current === null) this.el.text.textContent = fullRenderText(total);
    this.show();
  }

  // A step request failed (the server gone, say): playing stops, the controls go back to the
  // picture on screen and the step text says why.
  failed(message) {
    this.setPlaying(false);
    this.current = this.shownStep;
    this.el.text.textContent = tr({ en: `stepping stopped: ${message}`, ru: `пошаговый показ остановлен: ${message}` });
    this.show();
  }

  // A new algorithm, model, camera or size: the count is unknown until the server answers.
  invalidate() {
    this.total = null;
    this.show();
  }

  show() {
    const { slider, number, totalText } = this.el;
    const total = this.total ?? Math.max(1, this.current ?? 1);
    slider.max = String(total);
    number.max = String(total);
    const shown = this.current ?? total;
    slider.value = String(shown);
    // The full render before its step count is known has no number yet.
    number.value = this.current === null && this.total === null ? '' : String(shown);
    totalText.textContent = `/ ${this.total ?? '–'}`;
    if (this.onShown) this.onShown();
  }
}

// The step bar's text for step k (the plugin's text, or the host's, in the page's language) and for
// the full render with its step count (null: not known yet).
export function stepText(k, text) {
  return tr({ en: `step ${k}: ${text}`, ru: `шаг ${k}: ${text}` });
}

export const playLabel = (playing) => (playing ? tr({ en: 'pause', ru: 'пауза' }) : tr({ en: 'play', ru: 'пуск' }));

export function fullRenderText(total) {
  if (total === null || total === undefined) return tr({ en: 'the full render', ru: 'полное изображение' });
  return tr({ en: `the full render (${total} steps)`, ru: `полное изображение (шагов: ${total})` });
}

// Inputs that take no typing: the step keys act while one of them has the focus.
const UNTYPED_INPUTS = new Set(['checkbox', 'radio', 'range', 'button', 'submit', 'reset', 'file', 'color', 'image']);

// Does the focused element take typed text (a text or number input, a textarea, editable content)?
function typesText(target) {
  if (!(target instanceof Element)) return false;
  if (target instanceof HTMLTextAreaElement || target.isContentEditable) return true;
  return target instanceof HTMLInputElement && !UNTYPED_INPUTS.has(target.type);
}

// Draws one step's highlight on the overlay canvas (cleared first); steps null clears it. The
// canvas comes sized as the picture (redraw() in app.js); shown enlarged, it is drawn at the
// screen's resolution instead, so that lines and boxes stay 2 CSS pixels wide at any picture size.
export function drawStepOverlay(canvas, steps) {
  const pictureWidth = canvas.width, pictureHeight = canvas.height;
  const shownWidth = canvas.getBoundingClientRect().width || pictureWidth;
  const devicePixels = shownWidth * (window.devicePixelRatio || 1);
  // A hidden-line step draws itself on the picture's own pixels (drawLineStep).
  const factor = steps && isLineStep(steps) ? 1
    : Math.max(1, Math.min(Math.floor(devicePixels / pictureWidth), Math.floor(4096 / Math.max(pictureWidth, pictureHeight))));
  if (factor > 1) {
    canvas.width = pictureWidth * factor;
    canvas.height = pictureHeight * factor;
  }
  const ctx = canvas.getContext('2d');
  ctx.setTransform(1, 0, 0, 1, 0, 0);
  ctx.clearRect(0, 0, canvas.width, canvas.height);
  showLineStepKey(steps);
  if (!steps) return;
  if (isLineStep(steps)) {
    drawLineStep(canvas, steps);
    return;
  }
  ctx.setTransform(factor, 0, 0, factor, 0, 0);
  // Picture pixels per CSS pixel: lines are 2 CSS pixels wide whatever the picture's scale.
  const scale = pictureWidth / shownWidth;
  const minimum = 2 * scale;
  const dots = (points, color) => {
    if (!Array.isArray(points)) return;
    ctx.fillStyle = color;
    for (const [x, y] of points) ctx.fillRect(x, y, 1, 1);
  };
  ctx.globalAlpha = 0.85;
  dots(steps.rejected, ROLE_COLORS[2]);
  dots(steps.written, ROLE_COLORS[1]);
  ctx.globalAlpha = 1;
  ctx.lineWidth = minimum;
  // A line shorter than the minimum width (a side of a node's box a pixel or less across) is drawn
  // as a square that wide around its middle, so that the smallest box still shows.
  const segment = (x0, y0, x1, y1) => {
    if (Math.hypot(x1 - x0, y1 - y0) >= minimum) {
      ctx.moveTo(x0, y0);
      ctx.lineTo(x1, y1);
    } else {
      const cx = (x0 + x1) / 2, cy = (y0 + y1) / 2;
      ctx.rect(cx - minimum / 2, cy - minimum / 2, minimum, minimum);
    }
  };
  if (Array.isArray(steps.outline)) {
    ctx.strokeStyle = OUTLINE_COLOR;
    ctx.beginPath();
    for (const [x0, y0, x1, y1] of steps.outline) segment(x0, y0, x1, y1);
    ctx.stroke();
  }
  if (Array.isArray(steps.lines)) {
    for (const [x0, y0, x1, y1, role] of steps.lines) {
      ctx.strokeStyle = ROLE_COLORS[role] ?? ROLE_COLORS[0];
      ctx.beginPath();
      segment(x0, y0, x1, y1);
      ctx.stroke();
    }
  }
}
