// A plugin's parameter form, generated from its schema (/api/plugins): bool -> checkbox, enum ->
// select, int/float -> number with min/max, color -> colour picker, string -> text. Values are kept
// as the strings the CLI takes; only those that differ from the default are sent, so the request
// reads like the shortest equivalent command line.

import { tr, pluginText } from './i18n.js';

function colorToHex(text) {
  const t = String(text).trim();
  if (/^#[0-9a-f]{6}$/i.test(t)) return t.toLowerCase();
  const parts = t.split('/').map(Number);
  if (parts.length !== 3 || parts.some((v) => !Number.isFinite(v))) return '#000000';
  return '#' + parts.map((v) => Math.round(Math.min(1, Math.max(0, v)) * 255)
    .toString(16).padStart(2, '0')).join('');
}

function makeInput(param, plugin) {
  let input;
  switch (param.type) {
    case 'bool':
      input = document.createElement('input');
      input.type = 'checkbox';
      break;
    case 'enum':
      input = document.createElement('select');
      for (const choice of param.choices || []) {
        input.add(new Option(pluginText(plugin, `choice:${param.name}:${choice}`, choice), choice));
      }
      break;
    case 'int':
    case 'float':
      input = document.createElement('input');
      input.type = 'number';
      input.step = param.type === 'int' ? '1' : 'any';
      if (typeof param.min === 'number') input.min = String(param.min);
      if (typeof param.max === 'number') input.max = String(param.max);
      break;
    case 'color':
      input = document.createElement('input');
      input.type = 'color';
      break;
    default:
      input = document.createElement('input');
      input.type = 'text';
  }
  input.name = param.name;
  return input;
}

function readInput(param, input) {
  if (param.type === 'bool') return input.checked ? 'true' : 'false';
  return input.value.trim();
}

function writeInput(param, input, text) {
  if (param.type === 'bool') input.checked = text === 'true';
  else if (param.type === 'color') input.value = colorToHex(text);
  else input.value = text;
}

function isDefault(param, text) {
  if (param.type === 'color') return colorToHex(text) === colorToHex(param.default);
  return text === String(param.default);
}

export class ParamForm {
  // form: the <form> to fill; onChange(values) is called after the user changes a field.
  constructor(form, onChange) {
    this.form = form;
    this.onChange = onChange;
    this.params = [];
    this.userValues = {};
    form.addEventListener('submit', (e) => e.preventDefault());
  }

  // Builds the fields of `plugin`'s params (an /api/plugins entry, or null for none), showing
  // `values` (name -> text) where given, defaults elsewhere, in the plugin's words for the page's
  // language where it gives them.
  setSchema(plugin, values = {}) {
    this.plugin = plugin;
    this.params = plugin?.params || [];
    this.userValues = {};
    this.form.replaceChildren();
    if (this.params.length === 0) {
      const none = document.createElement('p');
      none.className = 'hint';
      none.textContent = tr({ en: 'no parameters', ru: 'нет параметров' });
      this.form.append(none);
      return;
    }
    for (const param of this.params) {
      const field = document.createElement('div');
      field.className = `field field-${param.type}`;
      field.dataset.name = param.name;
      const label = document.createElement('label');
      const name = document.createElement('span');
      name.className = 'field-name';
      name.textContent = pluginText(plugin, `param:${param.name}`, param.name);
      const help = pluginText(plugin, `help:${param.name}`, param.help);
      const input = makeInput(param, plugin);
      const given = values[param.name];
      const text = typeof given === 'string' ? given : String(param.default);
      writeInput(param, input, text);
      if (!isDefault(param, text)) this.userValues[param.name] = text;
      // The identifier the command line takes, for a label in another language.
      label.title = name.textContent === param.name ? help || '' : `${param.name}${help ? ` — ${help}` : ''}`;
      input.addEventListener('change', () => this.fieldChanged(param, input));
      if (param.type === 'bool') label.append(input, name);
      else label.append(name, input);
      const error = document.createElement('span');
      error.className = 'field-error';
      error.setAttribute('role', 'alert');
      field.append(label, error);
      if (help) {
        const helpLine = document.createElement('small');
        helpLine.className = 'field-help';
        helpLine.textContent = help;
        field.append(helpLine);
      }
      this.form.append(field);
    }
    const reset = document.createElement('button');
    reset.type = 'button';
    reset.className = 'secondary small';
    reset.textContent = tr({ en: 'defaults', ru: 'по умолчанию' });
    reset.addEventListener('click', () => {
      this.setSchema(this.plugin, {});
      this.onChange(this.values());
    });
    this.form.append(reset);
  }

  fieldChanged(param, input) {
    const text = readInput(param, input);
    if (isDefault(param, text)) delete this.userValues[param.name];
    else this.userValues[param.name] = text;
    this.showError(param.name, '');
    this.onChange(this.values());
  }

  values() {
    return { ...this.userValues };
  }

  showError(name, message) {
    const field = this.form.querySelector(`.field[data-name="${CSS.escape(name)}"]`);
    if (!field) return false;
    field.querySelector('.field-error').textContent = message;
    field.classList.toggle('invalid', Boolean(message));
    return true;
  }

  clearErrors() {
    for (const param of this.params) this.showError(param.name, '');
  }
}

// Fills a <select> with groups [[label, [{value, text}]]], choosing `selected` if it is there;
// returns the value chosen.
export function fillSelect(select, groups, selected) {
  select.replaceChildren();
  for (const [label, items] of groups) {
    if (!items.length) continue;
    const group = document.createElement('optgroup');
    group.label = label;
    for (const item of items) group.append(new Option(item.text, item.value));
    select.append(group);
  }
  if ([...select.options].some((o) => o.value === selected)) select.value = selected;
  return select.value;
}
