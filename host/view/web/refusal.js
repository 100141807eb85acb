// The whole reason a frame was not drawn, wrapped above the pictures: the error line of the top bar
// holds one line and cuts a long message, such as a hidden-line plugin's refusal of a model whose
// bodies are not convex. Shown for an error the server answered 4xx without a field to mark.
//
// Which models a plugin refuses is not marked in the model list: the server cannot tell without
// running the plugin on the model (the convexity checks are the plugin's own).

import { tr } from './i18n.js';

export function showRefusal(message, { algorithm = '', model = '' } = {}) {
  let box = document.getElementById('refusal');
  if (!box) {
    box = document.createElement('div');
    box.id = 'refusal';
    box.className = 'refusal';
    box.setAttribute('role', 'status');
    const title = document.createElement('strong');
    title.className = 'refusal-title';
    const text = document.createElement('p');
    text.className = 'refusal-text';
    box.append(title, text);
    const pictures = document.getElementById('pictures');
    pictures.parentElement.insertBefore(box, pictures);
  }
  box.hidden = !message;
  if (!message) return;
  const name = model.replace(/^\d+\//, '');
  box.querySelector('.refusal-title').textContent = algorithm && name
    ? tr({ en: `${algorithm} did not draw ${name}:`, ru: `${algorithm} не нарисовал ${name}:` })
    : tr({ en: 'Not drawn:', ru: 'Не нарисовано:' });
  box.querySelector('.refusal-text').textContent = message;
}
