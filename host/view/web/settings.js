// The viewer's settings (model, algorithm, lighting, parameters, camera, size, panels, language,
// presentation view) kept in localStorage between visits. A missing or unreadable store gives the defaults.

const KEY = 'hsr-view-settings';

export const DEFAULT_SETTINGS = Object.freeze({
  model: null, algorithm: 'zbuffer', lighting: 'blinn-phong',
  params: {}, lightingParams: {},          // plugin name -> {param: text}
  camera: null, width: 512, height: 512,
  bufferView: 'frame', gridMode: 'depth', speed: '1',
  compare: false, compareAlgorithm: null, theoryOpen: false,
  language: null,                          // 'en' or 'ru'; null: the browser's (i18n.js)
  presentation: false,                     // the presentation view (presentation.js)
  initialModel: null,                      // the model hsr view was started with, last visit
});

export function loadSettings() {
  try {
    const stored = JSON.parse(localStorage.getItem(KEY) || '{}');
    const settings = { ...DEFAULT_SETTINGS, ...(stored && typeof stored === 'object' ? stored : {}) };
    // A store written by hand or by another page must not break this one.
    for (const key of Object.keys(DEFAULT_SETTINGS)) {
      const expected = DEFAULT_SETTINGS[key];
      if (expected !== null && typeof settings[key] !== typeof expected) settings[key] = expected;
    }
    for (const key of ['params', 'lightingParams']) settings[key] = { ...settings[key] };
    return settings;
  } catch {
    return { ...DEFAULT_SETTINGS };
  }
}

export function saveSettings(settings) {
  try {
    localStorage.setItem(KEY, JSON.stringify(settings));
  } catch {
    // Private browsing or a full store: the page works without remembering.
  }
}
