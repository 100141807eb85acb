// The viewer page: loads the models and plugins, keeps the settings, asks the server for frames
// (latest wins) and shows them with their steps, buffers, stats, comparison and theory.

import { getJson, postJson, postJsonAside, cancelFrame, getProgress, ApiError } from './api.js';
import { Camera, cliCameraOptions } from './camera.js';
import { ParamForm, fillSelect } from './form.js';
import { ModelList } from './models.js';
import { StepControls, drawStepOverlay } from './steps.js';
import {
  BUFFER_NAMES, VIEW_BUFFER, decodeFrameBuffers, decodeStepBuffers, bufferView, drawLegend, pixelInfo, drawGrid, tileAround,
} from './buffers.js';
import { compareRequest, showCompare, hideCompare } from './compare.js';
import { renderStats } from './stats.js';
import { LatestWins } from './scheduler.js';
import { loadSettings, saveSettings } from './settings.js';
import { TheoryPane } from './theory.js';
import { onLanguageChange } from './i18n.js';

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
  setStatus(placed ? 'not rendered: see the marked field' : 'not rendered');
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


function algorithmChosen() {
  const algorithm = currentAlgorithm();
  $('algorithm-description').textContent = algorithm ? algorithm.description : '';
  paramForm.setSchema(algorithm ? algorithm.params : [], settings.params[settings.algorithm] || {});
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
  lightingForm.setSchema(lighting ? lighting.params : [], settings.lightingParams[settings.lighting] || {});
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

// ---- frames ----------------------------------------------------------------------------------

// Small pictures (exercise scenes) get the pixel grid: the one shown, or the one asked for.
function smallImage(size) {
  return size.width <= GRID_MAX_SIDE && size.height <= GRID_MAX_SIDE;
}

const gridShown = (size) => smallImage(size) && settings.gridMode !== 'off';

// The buffers the page shows: a buffer view's buffer (and the grid's depths) over the whole
// picture; for the readout, every buffer over the tile under the mouse (the whole of a small picture).
function wantBuffers() {
  if (camera.dragging) return false;
  const whole = new Set();
  if (VIEW_BUFFER[settings.bufferView]) whole.add(VIEW_BUFFER[settings.bufferView]);
  if (gridShown(settings) && settings.gridMode === 'depth') whole.add('depth');
  if (hovering && smallImage(settings)) BUFFER_NAMES.forEach((name) => whole.add(name));
  const specs = whole.size ? [{ names: [...whole] }] : [];
  if (hovering && pointer && !smallImage(settings)) specs.push({ names: BUFFER_NAMES, region: tileAround(pointer.x, pointer.y) });
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
  if (settings.compare && settings.compareAlgorithm) {
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
      }, roundTrip);
    } else {
      hideCompare(compareElements);
      renderStats($('stats'), '', frame.stats, roundTrip);
      if (request.step === null || request.step === undefined) askStepTotal(request);
    }
    clearFieldErrors();
    showError('');
    setStatus(`rendered in ${Math.round(roundTrip)} ms`);
    canvas.dataset.state = 'ready';
  } catch (e) {
    if (isStale()) return;
    if (e instanceof ApiError && e.status === 409) {  // stopped with Stop
      canvas.dataset.state = 'ready';
      setStatus('stopped');
      return;
    }
    canvas.dataset.state = 'error';
    if (!(e instanceof ApiError)) console.error(e);
    reportError(e instanceof ApiError ? e : new Error(`could not show the frame: ${e.message}`));
    if (job.kind === 'frame' && job.body.step !== null && job.body.step !== undefined) steps.failed(e.message);
    else if (steps.playing) steps.setPlaying(false);
  }
}

// A full render's answer has no step count: ask for step 1 aside for the count, so the step bar
// shows it before any step, and take it if the view is still the same when it comes.
const viewKey = (request) => JSON.stringify({ ...request, step: null, buffers: null });
let totalAskedFor = null;
async function askStepTotal(request) {
  if (!currentAlgorithm()?.steps || settings.compare || steps.total !== null) return;
  const key = viewKey(request);
  if (totalAskedFor === key) return;
  totalAskedFor = key;
  try {
    const answer = await postJsonAside('/api/frame', { ...request, step: 1, buffers: false });
    const total = answer.steps?.total;
    if (steps.total === null && Number.isFinite(total) && viewKey(frameRequest()) === key) steps.setTotal(total);
  } catch {
    // the count comes with the first step instead
  } finally {
    if (totalAskedFor === key) totalAskedFor = null;
  }
}

// While a frame takes long, the status counts its seconds and Stop cancels it.
const STOP_AFTER_MS = 1000;
let busyTimer = null;
const scheduler = new LatestWins(runJob, (busy) => {
  document.body.classList.toggle('busy', busy);
  clearInterval(busyTimer);
  $('stop').hidden = true;
  if (busy) {
    $('canvas').dataset.state = 'loading';
    setStatus('rendering…');
    busyTimer = setInterval(async () => {
      const ms = scheduler.running();
      if (ms === null || ms < STOP_AFTER_MS) return;
      $('stop').hidden = false;
      let text = `rendering… ${Math.floor(ms / 1000)} s`;
      try {
        const { progress } = await getProgress();
        if (progress && progress.total > 0) {
          text = `step ${progress.steps.toLocaleString('en')} of ${progress.total.toLocaleString('en')}… ${Math.floor(ms / 1000)} s`;
        } else if (progress) {
          text = `counting the steps: ${progress.steps.toLocaleString('en')} so far… ${Math.floor(ms / 1000)} s`;
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
      setStatus(shown.response.kind === 'lines' ? 'a line drawing has no buffers' : 'loading the buffers…');
      askForBuffers();
    }
  }
  drawLegend({ box: $('legend'), bar: $('legend-bar'), min: $('legend-min'), max: $('legend-max'), title: $('legend-title') }, legend);
  drawStepOverlay(overlay, shown.isStep ? shown.response.steps : null);
  const grid = $('grid');
  $('grid-control').hidden = !smallImage(shown.response);
  grid.hidden = !gridShown(shown.response);
  if (!grid.hidden) {
    if (settings.gridMode === 'depth' && !shown.frameBuffers?.whole.depth) askForBuffers();
    drawGrid(grid, { width, height, rgba: shown.rgba, frameBuffers: shown.frameBuffers, mode: settings.gridMode,
      steps: shown.isStep ? shown.response.steps : null });
  }
  updatePixelInfo();
}

function updateBufferOptions() {
  const select = $('buffer-select');
  for (const option of [...select.options]) {
    if (option.value.startsWith('step:')) option.remove();
  }
  for (const b of shown.stepBuffers) select.add(new Option(`${b.name} (${b.width}×${b.height})`, `step:${b.name}`));
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
    info.textContent = 'hover the picture for a pixel\'s depth and face';
    return;
  }
  if (shown.response.kind === 'lines') {
    info.textContent = `${pointer.x}, ${pointer.y}: a line drawing has no depth buffer`;
  } else if (pixelInfo(shown.frameBuffers, pointer.x, pointer.y) !== null) {
    info.textContent = pixelInfo(shown.frameBuffers, pointer.x, pointer.y);
  } else {
    info.textContent = `${pointer.x}, ${pointer.y}: ${hovering ? 'loading the buffers…' : 'rest the mouse for its depth'}`;
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

function setTheoryOpen(open) {
  settings.theoryOpen = open;
  $('theory').hidden = !open;
  $('layout').classList.toggle('with-theory', open);
  $('theory-toggle').setAttribute('aria-pressed', String(open));
  if (open) loadTheory();
  saveSettings(settings);
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
  if (body.step) words.push(`--step ${body.step}`);
  words.push('-o', algorithm && algorithm.kind === 'hidden_line' ? 'drawing.png' : 'picture.png');
  $('cli').textContent = words.join(' ');
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
    changed({ resetSteps: true });
  });
  $('upload').addEventListener('change', (e) => {
    if (e.target.files[0]) modelList.upload(e.target.files[0]);
    e.target.value = '';
  });
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
  modelList.acceptDrops($('drop-target'));
}

async function start() {
  // For scripts that drive the page (tests/browser): the last frame asked for and shown, whether
  // anything is on its way, and the camera as the controls hold it now.
  window.hsrView = {
    lastRequest: null, lastResponse: null, idle: () => scheduler.idle(), camera: () => camera.request(),
  };
  wire();
  let info;
  let models;
  try {
    [info, plugins] = await Promise.all([getJson('/api/info'), getJson('/api/plugins')]);
    models = (await getJson('/api/models')).models || [];
  } catch (e) {
    reportError(e);
    setStatus('the server did not answer');
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
  settings.model = modelList.set(models, settings.model);

  const option = (p) => ({ value: p.name, text: p.steps ? `${p.name} (steps)` : p.name });
  settings.algorithm = fillSelect($('algorithm'), [
    ['hidden surface', plugins.hidden_surface.map(option)],
    ['hidden line', plugins.hidden_line.map(option)],
  ], settings.algorithm);
  settings.lighting = fillSelect($('lighting'), [['lighting', plugins.lighting.map(option)]], settings.lighting);
  const others = plugins.hidden_surface.filter((p) => p.name !== settings.algorithm);
  settings.compareAlgorithm = fillSelect($('compare-algorithm'), [['hidden surface', plugins.hidden_surface.map(option)]],
    settings.compareAlgorithm || others[0]?.name || settings.algorithm);
  $('compare-toggle').checked = settings.compare;
  $('step-speed').value = settings.speed;
  $('width').value = String(settings.width);
  $('height').value = String(settings.height);
  $('buffer-select').value = settings.bufferView;
  $('grid-mode').value = settings.gridMode;
  camera.set(settings.camera);
  algorithmChosen();
  lightingChosen();
  setTheoryOpen(settings.theoryOpen);
  saveSettings(settings);
  if (!settings.model) {
    showError('no models found: start hsr view with a model file, --models DIR, or drop a file here');
    setStatus('no model');
    return;
  }
  requestFrame();
}

start();
