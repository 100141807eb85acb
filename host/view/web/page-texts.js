// The words of index.html in both languages. An element marked data-i18n="key" takes the entry's
// texts: `text` replaces its own words (the first text inside it that is not blank, so a label keeps
// the control it holds), `title`, `label` (aria-label), `placeholder` and `alt` its attributes.
// An entry given as {en, ru} alone is a text. applyPageTexts() runs at start and on every change
// of language.

import { tr } from './i18n.js';

export const PAGE_TEXTS = {
  'stop': {
    text: { en: 'Stop', ru: 'Стоп' },
    title: { en: 'stop the frame being rendered', ru: 'прервать отрисовку кадра' },
  },
  'theory-toggle': {
    text: { en: 'Theory', ru: 'Теория' },
    title: { en: 'show the algorithm\'s theory beside the picture', ru: 'показать теорию алгоритма рядом с изображением' },
  },
  'presentation-toggle': {
    text: { en: 'Present', ru: 'Показ' },
    title: {
      en: 'the picture and the step text large, the controls small, for a projector (key P; Esc leaves)',
      ru: 'крупное изображение и текст шага, мелкие элементы управления — для проектора (клавиша P, выход — Esc)',
    },
  },
  'language-choice': { label: { en: 'language of the page', ru: 'язык страницы' } },
  'language-en': { title: { en: 'English', ru: 'английский' } },
  'language-ru': { title: { en: 'Russian', ru: 'русский' } },

  'controls': { label: { en: 'controls', ru: 'управление' } },
  'model-heading': { en: 'Model', ru: 'Модель' },
  'model': { en: 'model', ru: 'модель' },
  'upload': {
    text: { en: 'upload a file…', ru: 'загрузить файл…' },
    title: { en: 'send a model file from this computer to the viewer', ru: 'передать программе файл модели с этого компьютера' },
  },
  'drop-hint': { en: 'or drop a model file anywhere on the page', ru: 'или перетащите файл модели в любое место страницы' },
  'algorithm-heading': { en: 'Algorithm', ru: 'Алгоритм' },
  'visibility': { en: 'visibility', ru: 'метод' },
  'lighting-heading': { en: 'Lighting', ru: 'Освещение' },
  'lighting': { en: 'model', ru: 'модель' },

  'camera-heading': { en: 'Camera', ru: 'Камера' },
  'projection': { en: 'projection', ru: 'проекция' },
  'perspective': { en: 'perspective', ru: 'перспективная' },
  'orthographic': { en: 'orthographic', ru: 'ортографическая' },
  'yaw': { en: 'yaw', ru: 'азимут' },
  'pitch': { en: 'pitch', ru: 'наклон' },
  'zoom': { en: 'zoom', ru: 'масштаб' },
  'fov': { en: 'fov°', ru: 'обзор°' },
  'look-at': { en: 'look-at camera', ru: 'камера: глаз и цель' },
  'eye-label': { en: 'eye', ru: 'глаз' },
  'eye': { placeholder: { en: 'x,y,z (empty: orbit)', ru: 'x,y,z (пусто — орбита)' } },
  'target-label': { en: 'target', ru: 'цель' },
  'target': { placeholder: { en: 'x,y,z (default: centre)', ru: 'x,y,z (по умолчанию — центр)' } },
  'up-label': { en: 'up', ru: 'верх' },
  'up': { placeholder: { en: 'x,y,z (default 0,1,0)', ru: 'x,y,z (по умолчанию 0,1,0)' } },
  'width': { en: 'width', ru: 'ширина' },
  'height': { en: 'height', ru: 'высота' },
  'camera-reset': { en: 'reset camera', ru: 'сбросить камеру' },
  'camera-hint': { en: 'drag the picture to orbit, wheel to zoom', ru: 'перетаскивание — вращение камеры, колесо — масштаб' },

  'compare-heading': { en: 'Compare', ru: 'Сравнить' },
  'compare-with': { en: 'side by side with', ru: 'рядом с алгоритмом' },

  'picture-area': { label: { en: 'picture', ru: 'изображение' } },
  'show': { en: 'show', ru: 'показать' },
  'view-frame': { en: 'frame', ru: 'кадр' },
  'view-depth': { en: 'depth', ru: 'глубина' },
  'view-depth-complexity': { en: 'depth complexity', ru: 'глубинная сложность' },
  'view-depth-tests': { en: 'depth tests', ru: 'тесты глубины' },
  'pixel-grid': { en: 'pixel grid', ru: 'сетка пикселей' },
  'grid-depth': { en: 'depth', ru: 'глубина' },
  'grid-colour': { en: 'colour', ru: 'цвет' },
  'grid-off': { en: 'off', ru: 'нет' },
  'canvas': {
    label: { en: 'the rendered picture: drag to orbit, wheel to zoom', ru: 'изображение: перетаскивание — вращение камеры, колесо — масштаб' },
  },
  'compare-b': { alt: { en: 'the compared algorithm\'s picture', ru: 'изображение второго алгоритма' } },
  'compare-diff-image': {
    alt: { en: 'where the two visibility results differ, in magenta', ru: 'пиксели, в которых результаты двух алгоритмов расходятся, — пурпурным' },
  },
  'differing-pixels': { en: 'differing pixels:', ru: 'различающихся пикселей:' },

  'step-first': { title: { en: 'first step', ru: 'первый шаг' }, label: { en: 'first step', ru: 'первый шаг' } },
  'step-back': { title: { en: 'step back', ru: 'шаг назад' }, label: { en: 'step back', ru: 'шаг назад' } },
  'step-play': { title: { en: 'play / pause', ru: 'пуск / пауза' } },
  'step-forward': { title: { en: 'step forward', ru: 'шаг вперёд' }, label: { en: 'step forward', ru: 'шаг вперёд' } },
  'step-last': {
    title: { en: 'last step (the full picture)', ru: 'последний шаг (полное изображение)' },
    label: { en: 'last step', ru: 'последний шаг' },
  },
  'step-slider': { label: { en: 'step', ru: 'шаг' } },
  'step-number': { placeholder: { en: 'all', ru: 'все' }, label: { en: 'step number', ru: 'номер шага' } },
  'speed': { en: 'speed', ru: 'скорость' },
  'speed-1': { en: '1 step/s', ru: '1 шаг/с' },
  'speed-5': { en: '5 steps/s', ru: '5 шагов/с' },
  'speed-20': { en: '20 steps/s', ru: '20 шагов/с' },
  'speed-100': { en: '100 steps/s', ru: '100 шагов/с' },
  'speed-1000': { en: '1000 steps/s', ru: '1000 шагов/с' },
  'key-subject': { en: 'subject', ru: 'текущий' },
  'key-written': { en: 'written', ru: 'записан' },
  'key-rejected': { en: 'rejected', ru: 'отброшен' },
  'key-context': { en: 'context', ru: 'окружение' },
  'key-outline': { en: 'triangle', ru: 'треугольник' },
  'keys-hint': { en: 'space play · ← → step · Home End first, last', ru: 'пробел — пуск · ← → — шаг · Home End — первый, последний' },

  'stats-heading': { en: 'Stats', ru: 'Статистика' },
  'cli': { en: 'same picture from the command line:', ru: 'то же изображение из командной строки:' },
  'theory': { label: { en: 'theory', ru: 'теория' } },
  'drop-target': { en: 'drop a model file to upload it', ru: 'отпустите файл модели, чтобы загрузить его' },
};

const ATTRIBUTES = { title: 'title', label: 'aria-label', placeholder: 'placeholder', alt: 'alt' };

// Replaces an element's own words, keeping the spaces around them and the elements beside them.
function setOwnText(element, text) {
  const node = [...element.childNodes].find((n) => n.nodeType === Node.TEXT_NODE && n.textContent.trim());
  if (!node) {
    if (element.children.length === 0) element.textContent = text;
    return;
  }
  const [, before, , after] = node.textContent.match(/^(\s*)([\s\S]*?)(\s*)$/);
  node.textContent = before + text + after;
}

export function applyPageTexts(root = document) {
  for (const element of root.querySelectorAll('[data-i18n]')) {
    const entry = PAGE_TEXTS[element.dataset.i18n];
    if (!entry) continue;
    if ('en' in entry) {
      setOwnText(element, tr(entry));
      continue;
    }
    if (entry.text) setOwnText(element, tr(entry.text));
    for (const [field, attribute] of Object.entries(ATTRIBUTES)) {
      if (entry[field]) element.setAttribute(attribute, tr(entry[field]));
    }
  }
}

// One entry's text, for the code that writes an element's words again (the step text, say).
export const pageText = (key) => tr(PAGE_TEXTS[key].text ?? PAGE_TEXTS[key]);
