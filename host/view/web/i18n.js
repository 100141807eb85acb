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

// A plugin's own text in the page's language: its translation under the ABI key `key`
// ("description", "param:<name>", "help:<name>", "choice:<param>:<choice>", "phase:<name>",
// "counter:<name>"; /api/plugins lists them), or `english` when the plugin gives none.
export function pluginText(plugin, key, english) {
  return plugin?.translations?.[current]?.[key] ?? english;
}

// A step buffer's name as a person reads it: "buffer:<name>", or "buffer:<stem>" and the trailing
// number of a name like "z-pyramid-3".
export function pluginBufferText(plugin, name) {
  const own = plugin?.translations?.[current];
  if (own?.[`buffer:${name}`]) return own[`buffer:${name}`];
  const numbered = /^(.*)-(\d+)$/.exec(name);
  if (numbered && own?.[`buffer:${numbered[1]}`]) return `${own[`buffer:${numbered[1]}`]} ${numbered[2]}`;
  return name;
}
