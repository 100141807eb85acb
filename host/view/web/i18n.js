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
