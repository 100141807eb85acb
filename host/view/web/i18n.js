// The page's language: English or Russian. Every text a person reads goes through tr(), which
// picks the current language's version of a text given in both:
//   tr({ en: 'Step', ru: 'Шаг' })
// so that each module keeps its words beside its code. Listeners run when the language changes.

const LANGUAGES = ['en', 'ru'];
let current = 'en';
const listeners = [];

export function language() {
  return current;
}

export function setLanguage(code) {
  const next = LANGUAGES.includes(code) ? code : 'en';
  if (next === current) return;
  current = next;
  document.documentElement.lang = current;
  for (const listener of listeners) listener(current);
}

export function onLanguageChange(listener) {
  listeners.push(listener);
}

export function tr(texts) {
  return texts[current] ?? texts.en;
}

// The language the browser asks for: Russian when the first of navigator.languages that is English
// or Russian is Russian, else English.
export function browserLanguage(languages = navigator.languages?.length ? navigator.languages : [navigator.language]) {
  for (const tag of languages) {
    const base = String(tag || '').toLowerCase().split('-')[0];
    if (LANGUAGES.includes(base)) return base;
  }
  return 'en';
}

// A count as the page's language writes it: 12,345 or 12 345.
export function numberText(value) {
  return value.toLocaleString(current === 'ru' ? 'ru-RU' : 'en-US');
}
