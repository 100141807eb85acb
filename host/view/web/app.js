// The viewer page: loads the models and plugins, keeps the settings, asks the server for frames
// (latest wins) and shows them with their steps, buffers, stats, comparison and theory.
// Over 700 lines because it is where every panel meets the one frame request: each panel's own
// work (steps, outline, grid, theory, links, languages, presentation) is in a module of its own,
// and what stays here is the wiring between them and the request they all change.

import { getJson, postJson, postJsonAside, cancelFrame, getProgress, ApiError } from './api.js';
import { Camera, cliCameraOptions } from './camera.js';
import { ParamForm, fillSelect } from './form.js';
import { ModelList } from './models.js';
import { StepControls, drawStepOverlay, fullRenderText, playLabel } from './steps.js';
import { StepOutline, OutlineBar, fillWorkedExample } from './outline.js';
import { StepExport } from './step-export.js';
import {
  BUFFER_NAMES, VIEW_BUFFER, decodeFrameBuffers, decodeStepBuffers, bufferView, drawLegend, pixelInfo, drawGrid, tileAround,
  gridCells, cellsOfFont,
} from './buffers.js';
import { linkHash, readLink } from './link.js';
import { compareRequest, showCompare, hideCompare, compareMismatch, showCompareNote } from './compare.js';
import { showRefusal } from './refusal.js';
import { renderStats, counterLabels } from './stats.js';
import { LatestWins } from './scheduler.js';
import { SceneEditor } from './editor.js';
import { loadSettings, saveSettings } from './settings.js';
import { TheoryPane } from './theory.js';
import { tr, language, setLanguage, onLanguageChange, browserLanguage, numberText, pluginText, pluginBufferText } from './i18n.js';
import { applyPageTexts } from './page-texts.js';
import { PresentationView } from './presentation.js';

const $ = (id) => document.getElementById(id);
const GRID_MAX_SIDE = 64;

const settings = loadSettings();
let plugins = { hidden_surface: [], hidden_line: [], lighting: [] };
let limits = { max_image_side: 4096 };
let hovering = false;        // the mouse rests on the picture: frames carry their buffers
let hoverTimer = null;
const HOVER_REST_MS = 250;
let pointer = null;          // the pixel under the mouse
let frameSerial = 0;         // frames shown
let upgradeAskedFor = '';    // the frame (and tile) whose buffers were last asked for

// What is on screen: the last frame's request, response and decoded data.
let shown = null;

// ---- errors and status ---------------------------------------------------------------------

function showError(message) {
  const el = $('error');
  el.textContent = message || '';
  el.hidden = !message;
}

function setStatus(text) {
  $('status').textContent = text;
}

function clearFieldErrors() {
  paramForm.clearErrors();
  lightingForm.clearErrors();
  for (const el of document.querySelectorAll('.controls > .panel > .field-error, .look-at .field-error')) {
    el.textContent = '';
  }
}

// Shows an error next to the field at fault if there is one, else on the page's error line.
function reportError(error) {
  const message = String(error.message || error);
  const field = error.field || '';
  let placed = false;
  if (field.startsWith('params.')) placed = paramForm.showError(field.slice(7), message);
  else if (field.startsWith('lighting_params.')) placed = lightingForm.showError(field.slice(16), message);
  else if (field.startsWith('camera')) {
    $('look-at').open = true;
    document.querySelector('.field-error[data-field="camera"]').textContent = message;
    placed = true;
  } else if (field === 'width' || field === 'height') {
    document.querySelector('.field-error[data-field="width"]').textContent = message;
    placed = true;
  }
  showError(placed ? '' : message);
  setStatus(placed ? tr({ en: 'not rendered: see the marked field', ru: 'не отрисовано: см. отмеченное поле' })
    : tr({ en: 'not rendered', ru: 'не отрисовано' }));
}

// ---- plugins and forms -------------------------------------------------------------------------

function pluginByName(name) {
  for (const kind of ['hidden_surface', 'hidden_line', 'lighting']) {
    const p = (plugins[kind] || []).find((x) => x.name === name);
    if (p) return { ...p, kind };
  }
  return null;
}

const currentAlgorithm = () => pluginByName(settings.algorithm);

const paramForm = new ParamForm($('params'), (values) => {
  settings.params[settings.algorithm] = values;
  changed({ resetSteps: true });
});
const lightingForm = new ParamForm($('lighting-params'), (values) => {
  settings.lightingParams[settings.lighting] = values;
  changed({});
});


function algorithmDescribed() {
  const algorithm = currentAlgorithm();
  $('algorithm-description').textContent = algorithm ? pluginText(algorithm, 'description', algorithm.description) : '';
}

function algorithmChosen() {
  const algorithm = currentAlgorithm();
  algorithmDescribed();
  paramForm.setSchema(algorithm, settings.params[settings.algorithm] || {});
  const lines = algorithm && algorithm.kind === 'hidden_line';
  $('lighting').disabled = lines;
  $('lighting-params').classList.toggle('disabled', lines);
  $('steps').hidden = !(algorithm && algorithm.steps) || settings.compare;
  if (!algorithm?.steps) steps.setPlaying(false);
  steps.current = null;
  steps.invalidate();
  if (!$('theory').hidden) loadTheory();
}

function lightingChosen() {
  const lighting = pluginByName(settings.lighting);
  lightingForm.setSchema(lighting, settings.lightingParams[settings.lighting] || {});
}

// ---- camera and steps ------------------------------------------------------------------------

const camera = new Camera({
  projection: $('projection'), yaw: $('yaw'), pitch: $('pitch'), zoom: $('zoom'), fov: $('fov'),
  eye: $('eye'), target: $('target'), up: $('up'),
}, () => {
  settings.camera = camera.state;
  changed({});
});
camera.onDragEnd = () => restHover();

const steps = new StepControls({
  play: $('step-play'), back: $('step-back'), forward: $('step-forward'), first: $('step-first'),
  last: $('step-last'), slider: $('step-slider'), number: $('step-number'), speed: $('step-speed'),
  text: $('step-text'), totalText: $('step-total'),
}, () => requestFrame());

const phaseTitle = (name) => pluginText(currentAlgorithm(), `phase:${name}`,
  currentAlgorithm()?.phases?.find((phase) => phase.name === name)?.title || name);
const outlineBar = new OutlineBar(document.querySelector('#steps .step-buttons'), steps, phaseTitle);
const stepExport = new StepExport($('steps'), steps);

// ---- frames ----------------------------------------------------------------------------------

// Small pictures (exercise scenes) get the pixel grid: the one shown, or the one asked for.
function smallImage(size) {
  return size.width <= GRID_MAX_SIDE && size.height <= GRID_MAX_SIDE;
}

const gridShown = (size) => smallImage(size) && settings.gridMode !== 'off';

// The size of a `camera pixel` scene, which fixes it whatever the page asks: {model, width, height}.
let sceneSize = null;
const pictureSize = () => (sceneSize && sceneSize.model === settings.model ? sceneSize : settings);

// The width and height fields show the size rendered: a scene that fixes its own shows it, read-only.
function showSizeFields() {
  const fixed = sceneSize && sceneSize.model === settings.model;
  for (const side of ['width', 'height']) {
    const field = $(side);
    field.value = String(fixed ? sceneSize[side] : settings[side]);
    field.disabled = Boolean(fixed);
    field.title = fixed ? tr({ en: 'this scene (camera pixel) fixes its own size', ru: 'размер задан самой сценой (camera pixel)' }) : '';
  }
}

// The buffers the page shows: a buffer view's buffer (and the grid's depths) over the whole
// picture; for the readout, every buffer over the tile under the mouse (the whole of a small picture).
function wantBuffers() {
  if (camera.dragging) return false;
  const whole = new Set();
  if (VIEW_BUFFER[settings.bufferView]) whole.add(VIEW_BUFFER[settings.bufferView]);
  if (gridShown(pictureSize()) && settings.gridMode === 'depth') {
    whole.add('depth');
    whole.add('scene_z');
  }
  if (hovering && smallImage(pictureSize())) BUFFER_NAMES.forEach((name) => whole.add(name));
  const specs = whole.size ? [{ names: [...whole] }] : [];
  if (hovering && pointer && !smallImage(pictureSize())) specs.push({ names: BUFFER_NAMES, region: tileAround(pointer.x, pointer.y) });
  return specs.length ? specs : false;
}

// The shown frame lacks the buffers a view or the readout needs: ask for the same frame with them,
// once for each frame and tile.
function askForBuffers() {
  if (camera.dragging || !shown || shown.response.kind === 'lines') return;
  const key = `${frameSerial} ${pointer ? tileAround(pointer.x, pointer.y).join(',') : ''}`;
  if (upgradeAskedFor === key) return;
  upgradeAskedFor = key;
  requestFrame();
}

function frameRequest() {
  const algorithm = currentAlgorithm();
  return {
    model: settings.model,
    algorithm: settings.algorithm,
    params: settings.params[settings.algorithm] || {},
    lighting: settings.lighting,
    lighting_params: settings.lightingParams[settings.lighting] || {},
    camera: camera.request(),
    width: settings.width,
    height: settings.height,
    step: algorithm && algorithm.steps && !settings.compare ? steps.current : null,
    buffers: wantBuffers(),
    language: language(),
  };
}

function requestFrame() {
  if (!settings.model || !settings.algorithm) return;
  let body;
  try {
    body = frameRequest();
  } catch (e) {
    reportError(e);
    return;
  }
  updateLink();
  const comparing = settings.compare && settings.compareAlgorithm;
  const mismatch = comparing ? compareMismatch(plugins, settings.algorithm, settings.compareAlgorithm) : null;
  showCompareNote($('compare-algorithm'), mismatch);
  if (comparing && !mismatch) {
    scheduler.submit({ kind: 'compare', body: compareRequest(body, settings.compareAlgorithm) });
  } else {
    scheduler.submit({ kind: 'frame', body });
  }
}

// Any setting changed: remember it and render again.
function changed({ resetSteps }) {
  if (resetSteps) steps.invalidate();
  saveSettings(settings);
  requestFrame();
}

async function runJob(job, isStale) {
  const started = performance.now();
  const canvas = $('canvas');
  try {
    let response;
    let frame;
    if (job.kind === 'compare') {
      response = await postJson('/api/compare', job.body);
      frame = response.a;
    } else {
      response = await postJson('/api/frame', job.body);
      frame = response;
    }
    const image = new Image();
    image.src = frame.png;
    await image.decode();
    if (isStale()) return;
    const roundTrip = performance.now() - started;
    const request = job.kind === 'compare' ? job.body.a : job.body;
    showFrame(request, frame, image, roundTrip);
    if (job.kind === 'compare') {
      showCompare(compareElements, response, {
        a: `${request.algorithm}`, b: `${job.body.b.algorithm}`,
      }, roundTrip, {
        a: counterLabels([currentAlgorithm(), pluginByName(settings.lighting)]),
        b: counterLabels([pluginByName(job.body.b.algorithm), pluginByName(settings.lighting)]),
      });
    } else {
      hideCompare(compareElements);
      renderStats($('stats'), '', frame.stats, roundTrip, counterLabels([currentAlgorithm(), pluginByName(settings.lighting)]));
      askOutline(request);
    }
    clearFieldErrors();
    showError('');
    showRefusal('');
    sceneEditor.frameDone(request.model, null);
    setStatus(tr({ en: `rendered in ${Math.round(roundTrip)} ms`, ru: `отрисовано за ${Math.round(roundTrip)} мс` }));
    canvas.dataset.state = 'ready';
  } catch (e) {
    if (isStale()) return;
    if (e instanceof ApiError && e.status === 409) {  // stopped with Stop
      canvas.dataset.state = 'ready';
      setStatus(tr({ en: 'stopped', ru: 'остановлено' }));
      return;
    }
    canvas.dataset.state = 'error';
    sceneEditor.frameDone(job.kind === 'compare' ? job.body.a.model : job.body.model, e);
    if (!(e instanceof ApiError)) console.error(e);
    reportError(e instanceof ApiError ? e
      : new Error(tr({ en: `could not show the frame: ${e.message}`, ru: `не удалось показать кадр: ${e.message}` })));
    const asked = job.kind === 'compare' ? job.body.a : job.body;
    const refused = e instanceof ApiError && !e.field && e.status >= 400 && e.status < 500;
    showRefusal(refused ? e.message : '', { algorithm: asked.algorithm, model: asked.model });
    if (job.kind === 'frame' && job.body.step !== null && job.body.step !== undefined) steps.failed(e.message);
    else if (steps.playing) steps.setPlaying(false);
  }
}

// The outline of the view's steps (POST /api/steps), asked once per model, plugin, parameters,
// camera, size and language: it brings the step count, shown before any step is asked for, the
// coarse units of the step bar and the worked example of the theory pane. One is asked at a time;
// when it comes for a view no longer shown, the one shown is asked for next.
const outlineBody = (request) => ({ ...request, step: null, buffers: false, lighting: null, lighting_params: null, language: language() });
const outlineKey = (request) => JSON.stringify(outlineBody(request));
let outline = null;          // { key, value: StepOutline } of the last outline that came
let outlineAsking = null;    // the key of the outline in flight
async function askOutline(request) {
  if (!currentAlgorithm()?.steps || settings.compare || camera.dragging) return;
  const key = outlineKey(request);
  if (outline?.key === key) {
    showOutline();
    return;
  }
  if (outlineAsking !== null) return;
  outlineAsking = key;
  outlineBar.setOutline(null);
  try {
    const body = outlineBody(request);
    delete body.lighting;
    delete body.lighting_params;
    const value = new StepOutline(await postJsonAside('/api/steps', body), pluginByName(body.algorithm));
    outline = { key, value };
  } catch {
    // the count comes with the first step instead
  } finally {
    outlineAsking = null;
  }
  showOutline();
}

// The outline, if it is the shown view's, on the step bar and in the worked example; else ask for it.
function showOutline() {
  const request = frameRequestOrNull();
  if (!request) return;
  const current = outline && outline.key === outlineKey(request) ? outline.value : null;
  if (!current) {
    askOutline(request);
    fillWorkedExample($('theory'), null, {});
    return;
  }
  if (steps.total !== current.total) steps.setTotal(current.total);
  if (outlineBar.outline !== current) outlineBar.setOutline(current);
  fillWorkedExample($('theory'), current, {
    modelName: settings.model.replace(/^\d+\//, ''),
    phases: (currentAlgorithm()?.phases ?? []).map((phase) => ({ ...phase, title: phaseTitle(phase.name) })),
    goToStep: (k) => steps.go(k),
  });
}

function frameRequestOrNull() {
  if (!settings.model || !settings.algorithm) return null;
  try {
    return frameRequest();
  } catch {
    return null;
  }
}

onLanguageChange(() => {
  outlineBar.setOutline(outlineBar.outline);
  showOutline();
});

// While a frame takes long, the status counts its seconds and Stop cancels it.
const STOP_AFTER_MS = 1000;
let busyTimer = null;
const scheduler = new LatestWins(runJob, (busy) => {
  document.body.classList.toggle('busy', busy);
  clearInterval(busyTimer);
  $('stop').hidden = true;
  if (busy) {
    $('canvas').dataset.state = 'loading';
    setStatus(tr({ en: 'rendering…', ru: 'отрисовка…' }));
    busyTimer = setInterval(async () => {
      const ms = scheduler.running();
      if (ms === null || ms < STOP_AFTER_MS) return;
      $('stop').hidden = false;
      const seconds = Math.floor(ms / 1000);
      let text = tr({ en: `rendering… ${seconds} s`, ru: `отрисовка… ${seconds} с` });
      try {
        const { progress } = await getProgress();
        if (progress && progress.total > 0) {
          const [k, total] = [numberText(progress.steps), numberText(progress.total)];
          text = tr({ en: `step ${k} of ${total}… ${seconds} s`, ru: `шаг ${k} из ${total}… ${seconds} с` });
        } else if (progress) {
          const k = numberText(progress.steps);
          text = tr({ en: `counting the steps: ${k} so far… ${seconds} s`, ru: `подсчёт шагов: пока ${k}… ${seconds} с` });
        }
      } catch {
        // the status keeps its seconds
      }
      if (scheduler.running() !== null) setStatus(text);
    }, 500);
  }
});

function showFrame(request, response, image, roundTrip) {
  const rgbaCanvas = document.createElement('canvas');
  rgbaCanvas.width = response.width;
  rgbaCanvas.height = response.height;
  const rgbaContext = rgbaCanvas.getContext('2d', { willReadFrequently: true });
  rgbaContext.drawImage(image, 0, 0);
  shown = {
    request, response, image, roundTrip,
    rgba: rgbaContext.getImageData(0, 0, response.width, response.height).data,
    frameBuffers: decodeFrameBuffers(response.buffers, response.width, response.height),
    stepBuffers: decodeStepBuffers(response.steps),
    isStep: request.step !== null && request.step !== undefined,
  };
  frameSerial += 1;
  const fixesSize = response.pixel_camera === true;
  if (fixesSize) sceneSize = { model: request.model, width: response.width, height: response.height };
  else if (sceneSize?.model === request.model) sceneSize = null;
  showSizeFields();
  steps.frameShown(response.steps, shown.isStep);
  theoryPane.setPhase(shown.isStep ? response.steps?.phase : null);
  updateBufferOptions();
  redraw();
  updateCli(request, response);
  window.hsrView.lastRequest = request;
  window.hsrView.lastResponse = response;
  $('canvas').dataset.frame = String(frameSerial);
}

// The picture is drawn as large as the window lets it be (style.css, .stack): its pixels stay crisp
// squares whenever it is shown larger than it is.
function pixelateIfEnlarged() {
  const canvas = $('canvas');
  canvas.classList.toggle('pixelated', canvas.getBoundingClientRect().width > canvas.width);
}
new ResizeObserver(pixelateIfEnlarged).observe($('canvas'));

function redraw() {
  if (!shown) return;
  const canvas = $('canvas');
  const overlay = $('overlay');
  const { width, height } = shown.response;
  for (const c of [canvas, overlay]) {
    if (c.width !== width) c.width = width;
    if (c.height !== height) c.height = height;
  }
  canvas.closest('.stack').style.setProperty('--aspect', String(width / height));
  pixelateIfEnlarged();
  const ctx = canvas.getContext('2d');
  ctx.imageSmoothingEnabled = false;
  ctx.clearRect(0, 0, width, height);
  let legend = null;
  const view = settings.bufferView;
  const picture = view === 'frame' ? null : bufferView(view, shown.frameBuffers, shown.stepBuffers);
  if (picture) {
    if (picture.width === width && picture.height === height) {
      ctx.putImageData(picture.image, 0, 0);
    } else {
      const scratch = document.createElement('canvas');
      scratch.width = picture.width;
      scratch.height = picture.height;
      scratch.getContext('2d').putImageData(picture.image, 0, 0);
      ctx.drawImage(scratch, 0, 0, width, height);
    }
    legend = picture.legend;
  } else {
    ctx.drawImage(shown.image, 0, 0);
    if (view !== 'frame') {
      setStatus(shown.response.kind === 'lines' ? tr({ en: 'a line drawing has no buffers', ru: 'у штрихового рисунка нет буферов' })
        : tr({ en: 'loading the buffers…', ru: 'загрузка буферов…' }));
      askForBuffers();
    }
  }
  drawLegend({ box: $('legend'), bar: $('legend-bar'), min: $('legend-min'), max: $('legend-max'), title: $('legend-title') }, legend);
  drawStepOverlay(overlay, shown.isStep ? shown.response.steps : null);
  const grid = $('grid');
  $('grid-control').hidden = !smallImage(shown.response);
  grid.hidden = !gridShown(shown.response);
  $('grid-box').hidden = grid.hidden;
  if (!grid.hidden) {
    const whole = shown.frameBuffers?.whole;
    if (settings.gridMode === 'depth' && (!whole?.depth || (shown.response.pixel_camera && !whole.sceneZ))) askForBuffers();
    const table = drawGrid(grid, { width, height, rgba: shown.rgba, frameBuffers: shown.frameBuffers,
      mode: settings.gridMode, steps: shown.isStep ? shown.response.steps : null });
    showGridCaption(table);
    layoutGrid({ width, height }, table);
  } else {
    layoutGrid(null, null);
  }
  updateLink();
  updatePixelInfo();
}

function showGridCaption(table) {
  $('grid-label').textContent = table.label;
  const written = $('grid-written');
  const rejected = $('grid-rejected');
  written.hidden = !table.marked;
  rejected.hidden = !table.marked;
  written.textContent = tr({ en: `written by this step: ${table.written}`, ru: `записано на этом шаге: ${table.written}` });
  rejected.textContent = tr({ en: `rejected by the depth test: ${table.rejected}`,
    ru: `отброшено тестом глубины: ${table.rejected}` });
}

// The grid beside the picture when the window has room for all of it with a readable font
// (10 px, 8 px past 32 × 32), the picture taking what is left; else below the picture.
const GRID_GAP = 12;
const PICTURE_LEAST = 240;
function layoutGrid(size, table) {
  const centre = document.querySelector('.centre');
  const stack = $('canvas').closest('.stack');
  const grid = $('grid');
  centre.classList.remove('with-grid');
  centre.style.removeProperty('--grid-picture-width');
  stack.style.maxWidth = '';
  if (!size) return;
  const smallest = size.width > 32 || size.height > 32 ? 8 : 10;
  const comparing = Boolean(document.querySelector('.pictures.comparing'));
  const top = document.querySelector('.viewbar').getBoundingClientRect().bottom + window.scrollY + GRID_GAP
    + $('grid-caption').getBoundingClientRect().height + 6;
  const base = { columns: size.width, rows: size.height, characters: table.characters, lines: table.lines };
  // The picture keeps a third of the width if the grid fits beside it so, else PICTURE_LEAST.
  const beside = (picture) => {
    const room = { width: centre.clientWidth - picture - GRID_GAP - 4, height: window.innerHeight - top - 12 };
    return room.width > 0 && room.height > 0 ? gridCells({ ...base, room, smallest }) : null;
  };
  let cells = comparing ? null : beside(Math.max(PICTURE_LEAST, centre.clientWidth / 3)) || beside(PICTURE_LEAST);
  if (cells) {
    centre.classList.add('with-grid');
    const gridWidth = size.width * (cells.width + 1) + 3;
    const pictureWidth = Math.max(PICTURE_LEAST, centre.clientWidth - gridWidth - GRID_GAP);
    stack.style.maxWidth = `${pictureWidth}px`;
    centre.style.setProperty('--grid-picture-width', `${pictureWidth}px`);
  } else {
    const below = gridCells({ ...base, room: { width: centre.clientWidth - 4, height: 1e9 }, smallest: 10 });
    cells = below || cellsOfFont(10, table.characters, table.lines);
  }
  grid.style.setProperty('--cell-width', `${cells.width}px`);
  grid.style.setProperty('--cell-height', `${cells.height}px`);
  grid.style.fontSize = `${cells.font}px`;
}

function updateBufferOptions() {
  const select = $('buffer-select');
  for (const option of [...select.options]) {
    if (option.value.startsWith('step:')) option.remove();
  }
  for (const b of shown.stepBuffers) {
    select.add(new Option(`${pluginBufferText(currentAlgorithm(), b.name)} (${b.width}×${b.height})`, `step:${b.name}`));
  }
  if (![...select.options].some((o) => o.value === settings.bufferView)) {
    // A step buffer of an earlier step: keep asking for it, the next step may have it again.
    if (settings.bufferView.startsWith('step:')) select.add(new Option(settings.bufferView.slice(5), settings.bufferView));
    else settings.bufferView = 'frame';
  }
  select.value = settings.bufferView;
}

// ---- hover readout -----------------------------------------------------------------------------

function pixelUnder(event) {
  const canvas = $('canvas');
  const rect = canvas.getBoundingClientRect();
  const x = Math.floor(((event.clientX - rect.left) / rect.width) * canvas.width);
  const y = Math.floor(((event.clientY - rect.top) / rect.height) * canvas.height);
  if (x < 0 || y < 0 || x >= canvas.width || y >= canvas.height) return null;
  return { x, y };
}

function updatePixelInfo() {
  const info = $('pixel-info');
  if (!pointer || !shown) {
    info.textContent = tr({ en: 'hover the picture for a pixel\'s depth and face',
      ru: 'наведите указатель на изображение — появятся глубина и грань пикселя' });
    return;
  }
  if (shown.response.kind === 'lines') {
    info.textContent = tr({ en: `${pointer.x}, ${pointer.y}: a line drawing has no depth buffer`,
      ru: `${pointer.x}, ${pointer.y}: у штрихового рисунка нет буфера глубины` });
  } else if (pixelInfo(shown.frameBuffers, pointer.x, pointer.y) !== null) {
    info.textContent = pixelInfo(shown.frameBuffers, pointer.x, pointer.y);
  } else {
    info.textContent = `${pointer.x}, ${pointer.y}: ${hovering ? tr({ en: 'loading the buffers…', ru: 'загрузка буферов…' })
      : tr({ en: 'rest the mouse for its depth', ru: 'задержите указатель, чтобы узнать глубину' })}`;
    if (hovering) askForBuffers();
  }
}

// The buffers of a frame are large: the readout asks for them once the mouse rests on the picture,
// not while it passes over it or starts a drag.
function restHover() {
  clearTimeout(hoverTimer);
  hoverTimer = setTimeout(() => {
    if (!pointer || camera.dragging) return;
    hovering = true;
    updatePixelInfo();
  }, HOVER_REST_MS);
}

// ---- theory --------------------------------------------------------------------------------------

const theoryPane = new TheoryPane($('theory'), getJson);
onLanguageChange(() => { if (!$('theory').hidden) theoryPane.reload(); });

function loadTheory() {
  theoryPane.show(settings.algorithm);
}

// A page placed in the pane with an empty worked example gets it filled from the outline.
new MutationObserver(() => {
  if ($('theory').querySelector('div.worked-example:empty')) showOutline();
}).observe($('theory'), { childList: true });

function setTheoryOpen(open) {
  settings.theoryOpen = open;
  $('theory').hidden = !open;
  $('layout').classList.toggle('with-theory', open);
  $('theory-toggle').setAttribute('aria-pressed', String(open));
  if (open) loadTheory();
  saveSettings(settings);
  updateLink();
  if (shown) redraw();
}

// ---- the command line of the same picture ---------------------------------------------------------

// The size is the one rendered: a `camera pixel` scene keeps its own.
function updateCli(body, response) {
  const withParams = (name, values) => {
    const pairs = Object.entries(values || {}).map(([k, v]) => `${k}=${v}`);
    return pairs.length ? `${name}:${pairs.join(',')}` : name;
  };
  const model = body.model || '';
  const path = model.startsWith('upload/') ? model.split('/').slice(2).join('/') : model.split('/').slice(1).join('/');
  const algorithm = pluginByName(body.algorithm);
  const words = ['hsr render', path, '-a', withParams(body.algorithm, body.params)];
  if (!algorithm || algorithm.kind !== 'hidden_line') words.push('-l', withParams(body.lighting, body.lighting_params));
  words.push(`--width ${response.width}`, `--height ${response.height}`, ...cliCameraOptions(body.camera));
  stepExport.setBase(algorithm && algorithm.kind === 'hidden_line' ? null : [...words], body);
  if (body.step) words.push(`--step ${body.step}`);
  words.push('-o', algorithm && algorithm.kind === 'hidden_line' ? 'drawing.png' : 'picture.png');
  $('cli').textContent = words.join(' ');
}

// ---- the state in the URL ----------------------------------------------------------------------------

let linkReady = false;  // the link is written once the page has read the one it was opened with
let linkTimer = null;
let linkWritten = '';

function linkState() {
  return {
    model: settings.model, algorithm: settings.algorithm, params: settings.params[settings.algorithm] || {},
    lighting: settings.lighting, lightingParams: settings.lightingParams[settings.lighting] || {},
    camera: settings.camera || camera.state, width: settings.width, height: settings.height,
    step: currentAlgorithm()?.steps && !settings.compare ? steps.current : null,
    view: settings.bufferView, grid: settings.gridMode, theory: settings.theoryOpen,
    compare: settings.compare ? settings.compareAlgorithm : null,
  };
}

// The URL follows the page as it changes: at once, but for at most 40 rewrites in 10 s (browsers
// refuse history.replaceState called faster, as playing steps would); past that, every 250 ms.
const LINK_WRITES = 40;
const LINK_WINDOW_MS = 10_000;
const linkWriteTimes = [];
function writeLink() {
  clearTimeout(linkTimer);
  linkTimer = null;
  const hash = linkHash(linkState());
  if (hash === linkWritten) return;
  linkWritten = hash;
  linkWriteTimes.push(performance.now());
  try {
    history.replaceState(history.state, '', hash);
  } catch {
    // a page that may not rewrite its URL still works
  }
}

function updateLink() {
  if (!linkReady || linkTimer) return;
  const now = performance.now();
  while (linkWriteTimes.length && now - linkWriteTimes[0] > LINK_WINDOW_MS) linkWriteTimes.shift();
  if (linkWriteTimes.length < LINK_WRITES) writeLink();
  else linkTimer = setTimeout(writeLink, 250);
}

function showLinkMessage(text) {
  const el = $('link-message');
  el.textContent = text;
  el.hidden = !text;
}

// The state a link gives, over the stored settings; what does not fit the server's lists or the
// page's forms is left as it was, and said so.
function applyLink(models) {
  const link = readLink(window.location.hash, { maxImageSide: limits.max_image_side || 4096 });
  if (!link) return;
  const { state } = link;
  const bad = [...link.bad];
  const names = (kind) => (plugins[kind] || []).map((p) => p.name);
  if (state.model !== undefined) {
    if (models.some((m) => m.id === state.model)) settings.model = state.model;
    else bad.push('model');
  }
  if (state.algorithm !== undefined) {
    if ([...names('hidden_surface'), ...names('hidden_line')].includes(state.algorithm)) settings.algorithm = state.algorithm;
    else bad.push('algorithm');
  }
  // Parameters the plugin does not have are dropped; a value it refuses shows at its field.
  const known = (plugin, given, prefix) => {
    const names = new Set((plugin?.params || []).map((p) => p.name));
    const kept = {};
    for (const [name, value] of Object.entries(given)) {
      if (names.has(name)) kept[name] = value;
      else bad.push(`${prefix}${name}`);
    }
    return kept;
  };
  if (state.params) settings.params[settings.algorithm] = known(pluginByName(settings.algorithm), state.params, 'p.');
  if (state.lighting !== undefined) {
    if (names('lighting').includes(state.lighting)) settings.lighting = state.lighting;
    else bad.push('lighting');
  }
  if (state.lightingParams) {
    settings.lightingParams[settings.lighting] = known(pluginByName(settings.lighting), state.lightingParams, 'l.');
  }
  if (state.camera) settings.camera = { ...(settings.camera || {}), ...state.camera };
  for (const key of ['width', 'height']) if (state[key] !== undefined) settings[key] = state[key];
  if (state.view !== undefined) settings.bufferView = state.view;
  if (state.grid !== undefined) settings.gridMode = state.grid;
  if (state.theory !== undefined) settings.theoryOpen = state.theory;
  if (state.compare !== undefined) {
    if (names('hidden_surface').includes(state.compare) || names('hidden_line').includes(state.compare)) {
      settings.compare = true;
      settings.compareAlgorithm = state.compare;
    } else {
      bad.push('compare');
    }
  } else {
    settings.compare = false;
  }
  if (bad.length) {
    showLinkMessage(tr({ en: `the link's ${[...new Set(bad)].join(', ')} ignored: not a value this page knows`,
      ru: `в ссылке пропущено: ${[...new Set(bad)].join(', ')} — таких значений страница не знает` }));
  }
  return state.step ?? null;
}

async function copyLink() {
  writeLink();
  const url = window.location.href;
  try {
    await navigator.clipboard.writeText(url);
    showLinkMessage(tr({ en: 'link copied', ru: 'ссылка скопирована' }));
  } catch {
    showLinkMessage(tr({ en: `copy this link: ${url}`, ru: `скопируйте ссылку: ${url}` }));
  }
  $('copy-link').dataset.link = url;
}

// ---- models ------------------------------------------------------------------------------------------

const modelList = new ModelList($('model'), {
  onUploaded: (id) => {
    settings.model = id;
    steps.current = null;
    changed({ resetSteps: true });
  },
  onError: (e) => reportError(e),
  onStatus: (text) => setStatus(text),
});

// Each edit of the scene editor is a new upload that replaces the one before, in the list too.
const sceneEditor = new SceneEditor($('scene-editor-panel'), {
  models: () => modelList.models,
  currentModel: () => settings.model,
  show: (id, name, bytes, replaced) => {
    const others = modelList.models.filter((m) => m.id !== replaced);
    settings.model = modelList.set([...others, { id, name, bytes }], id);
    steps.current = null;
    showSizeFields();
    changed({ resetSteps: true });
  },
  onError: (e) => reportError(e),
});

// ---- wiring -----------------------------------------------------------------------------------------

const compareElements = {
  figures: [...document.querySelectorAll('.compare-picture')],
  pictures: $('pictures'), imageB: $('compare-b'), diffImage: $('compare-diff-image'),
  captionA: $('caption-a'), captionB: $('caption-b'), diffCount: $('compare-diff'),
  statsA: $('stats'), statsB: $('compare-stats'),
};

function wire() {
  $('model').addEventListener('change', (e) => {
    settings.model = e.target.value;
    steps.current = null;
    showSizeFields();
    changed({ resetSteps: true });
  });
  modelList.acceptPicks($('upload'), $('upload-choose'), $('upload-name'));
  $('algorithm').addEventListener('change', (e) => {
    settings.algorithm = e.target.value;
    algorithmChosen();
    changed({ resetSteps: true });
  });
  $('lighting').addEventListener('change', (e) => {
    settings.lighting = e.target.value;
    lightingChosen();
    changed({});
  });
  for (const side of ['width', 'height']) {
    $(side).addEventListener('change', (e) => {
      const v = Math.round(Number(e.target.value));
      settings[side] = Number.isFinite(v) ? v : settings[side];
      e.target.value = String(settings[side]);
      changed({ resetSteps: true });
    });
  }
  $('camera-reset').addEventListener('click', () => camera.reset());
  $('buffer-select').addEventListener('change', (e) => {
    settings.bufferView = e.target.value;
    saveSettings(settings);
    redraw();
  });
  $('grid-mode').addEventListener('change', (e) => {
    settings.gridMode = e.target.value;
    saveSettings(settings);
    redraw();
  });
  $('step-speed').addEventListener('change', (e) => {
    settings.speed = e.target.value;
    saveSettings(settings);
  });
  $('compare-toggle').addEventListener('change', (e) => {
    settings.compare = e.target.checked;
    $('steps').hidden = !currentAlgorithm()?.steps || settings.compare;
    if (settings.compare) steps.setPlaying(false);
    changed({});
  });
  $('compare-algorithm').addEventListener('change', (e) => {
    settings.compareAlgorithm = e.target.value;
    changed({});
  });
  $('theory-toggle').addEventListener('click', () => setTheoryOpen($('theory').hidden));
  $('copy-link').addEventListener('click', () => copyLink());
  const linkWords = () => {
    $('copy-link').textContent = tr({ en: 'copy link', ru: 'скопировать ссылку' });
    $('copy-link').title = tr({ en: 'copy a link to this picture and step', ru: 'скопировать ссылку на этот кадр и шаг' });
  };
  linkWords();
  onLanguageChange(() => {
    linkWords();
    showSizeFields();
    if (shown) redraw();
  });
  for (const button of document.querySelectorAll('.language-choice button')) {
    button.addEventListener('click', () => {
      settings.language = button.dataset.language;
      saveSettings(settings);
      languageChosen();
    });
  }
  $('stop').addEventListener('click', () => {
    if (steps.playing) steps.setPlaying(false);
    cancelFrame().catch(reportError);
  });

  const canvas = $('canvas');
  camera.attach(canvas);
  canvas.addEventListener('pointermove', (e) => {
    if (camera.dragging) return;
    pointer = pixelUnder(e);
    restHover();
    updatePixelInfo();
  });
  canvas.addEventListener('pointerdown', () => clearTimeout(hoverTimer));
  canvas.addEventListener('pointerleave', () => {
    clearTimeout(hoverTimer);
    hovering = false;
    pointer = null;
    updatePixelInfo();
  });
  window.addEventListener('resize', () => redraw());
  window.addEventListener('pagehide', () => {
    if (linkReady) writeLink();
  });
  // A link pasted into this tab's address bar: the page opens what it says.
  window.addEventListener('hashchange', () => {
    if (window.location.hash !== linkWritten) window.location.reload();
  });
  modelList.acceptDrops($('drop-target'));
}

// The plugin selects, grouped by kind; a plugin that steps is marked.
function fillPluginSelects() {
  const option = (p) => ({ value: p.name, text: p.steps ? tr({ en: `${p.name} (steps)`, ru: `${p.name} (по шагам)` }) : p.name });
  const surfaces = tr({ en: 'hidden surface', ru: 'удаление невидимых поверхностей' });
  settings.algorithm = fillSelect($('algorithm'), [
    [surfaces, plugins.hidden_surface.map(option)],
    [tr({ en: 'hidden line', ru: 'удаление невидимых линий' }), plugins.hidden_line.map(option)],
  ], settings.algorithm);
  settings.lighting = fillSelect($('lighting'), [[tr({ en: 'lighting', ru: 'освещение' }), plugins.lighting.map(option)]],
    settings.lighting);
  const sameKind = plugins.hidden_surface.some((p) => p.name === settings.algorithm) ? plugins.hidden_surface : plugins.hidden_line;
  const others = sameKind.filter((p) => p.name !== settings.algorithm);
  settings.compareAlgorithm = fillSelect($('compare-algorithm'), [
    [surfaces, plugins.hidden_surface.map(option)],
    [tr({ en: 'hidden line', ru: 'удаление невидимых линий' }), plugins.hidden_line.map(option)],
  ], settings.compareAlgorithm || others[0]?.name || settings.algorithm);
}

// ---- language and the presentation view -----------------------------------------------------------

// The page's words in the language chosen (settings.language, null: the browser's): the static ones
// at once, the rest with the frame asked for again (its step text comes from the server).
function languageChosen() {
  setLanguage(settings.language ?? browserLanguage());
  for (const button of document.querySelectorAll('.language-choice button')) {
    button.setAttribute('aria-pressed', String(button.dataset.language === language()));
  }
}

onLanguageChange(() => {
  applyPageTexts();
  $('step-play').setAttribute('aria-label', playLabel(steps.playing));
  if (steps.current === null) $('step-text').textContent = fullRenderText(steps.total);
  updatePixelInfo();
  if (!plugins.hidden_surface.length && !plugins.lighting.length) return;  // still starting
  fillPluginSelects();
  settings.model = modelList.set(modelList.models, settings.model);
  algorithmDescribed();
  paramForm.setSchema(currentAlgorithm(), settings.params[settings.algorithm] || {});
  lightingChosen();
  if (shown) redraw();
  requestFrame();
});

const presentation = new PresentationView($('presentation-toggle'), (on) => {
  settings.presentation = on;
  saveSettings(settings);
  if (shown) redraw();
});

async function start() {
  // For scripts that drive the page (tests/browser): the last frame asked for and shown, whether
  // anything is on its way, and the camera as the controls hold it now.
  window.hsrView = {
    lastRequest: null, lastResponse: null, idle: () => scheduler.idle(), camera: () => camera.request(),
  };
  // The outline of the view's steps once it came, and a way to fill the theory pane's worked
  // example again (after a script put one there).
  window.hsrView.outline = () => outline?.value ?? null;
  window.hsrView.showOutline = () => showOutline();
  wire();
  languageChosen();
  applyPageTexts();
  setStatus(tr({ en: 'starting…', ru: 'запуск…' }));
  presentation.set(settings.presentation);
  let info;
  let models;
  try {
    [info, plugins] = await Promise.all([getJson('/api/info'), getJson('/api/plugins')]);
    models = (await getJson('/api/models')).models || [];
  } catch (e) {
    reportError(e);
    setStatus(tr({ en: 'the server did not answer', ru: 'сервер не ответил' }));
    return;
  }
  for (const kind of ['hidden_surface', 'hidden_line', 'lighting']) {
    if (!Array.isArray(plugins[kind])) plugins[kind] = [];
  }
  limits = info.limits || limits;
  for (const side of ['width', 'height']) $(side).max = String(limits.max_image_side || 4096);
  // The model named on the command line comes first, unless this browser already saw that
  // command's model and chose another since.
  if (info.initial_model && info.initial_model !== settings.initialModel) settings.model = info.initial_model;
  settings.initialModel = info.initial_model || null;
  const linkStep = applyLink(models);
  settings.model = modelList.set(models, settings.model);

  fillPluginSelects();
  $('compare-toggle').checked = settings.compare;
  $('step-speed').value = settings.speed;
  $('width').value = String(settings.width);
  $('height').value = String(settings.height);
  $('buffer-select').value = settings.bufferView;
  $('grid-mode').value = settings.gridMode;
  camera.set(settings.camera);
  algorithmChosen();
  lightingChosen();
  if (linkStep !== null && linkStep !== undefined && currentAlgorithm()?.steps && !settings.compare) steps.current = linkStep;
  linkReady = true;
  setTheoryOpen(settings.theoryOpen);
  saveSettings(settings);
  if (!settings.model) {
    showError(tr({
      en: 'no models found: start hsr view with a model file, --models DIR, or drop a file here',
      ru: 'модели не найдены: запустите hsr view с файлом модели или с --models КАТАЛОГ либо перетащите файл сюда',
    }));
    setStatus(tr({ en: 'no model', ru: 'нет модели' }));
    return;
  }
  requestFrame();
}

start();
