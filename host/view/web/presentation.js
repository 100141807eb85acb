// The presentation view, for a projector: the picture and the step text large, the controls small
// (style.css, body.presentation). The header's button or the key P (outside a field that takes
// typing) switches it; Escape leaves it.

// Inputs that take no typing: P acts while one of them has the focus.
const UNTYPED_INPUTS = new Set(['checkbox', 'radio', 'range', 'button', 'submit', 'reset', 'file', 'color', 'image']);

function typesText(target) {
  if (!(target instanceof Element)) return false;
  if (target instanceof HTMLTextAreaElement || target.isContentEditable) return true;
  return target instanceof HTMLInputElement && !UNTYPED_INPUTS.has(target.type);
}

export class PresentationView {
  // button: the header's toggle; onChange(on) after every switch (to keep the setting, redraw).
  constructor(button, onChange) {
    this.button = button;
    this.onChange = onChange;
    button.addEventListener('click', () => this.set(!this.on));
    window.addEventListener('keydown', (e) => this.key(e), true);
  }

  get on() {
    return document.body.classList.contains('presentation');
  }

  set(on) {
    document.body.classList.toggle('presentation', on);
    this.button.setAttribute('aria-pressed', String(on));
    this.onChange(on);
  }

  key(e) {
    if (e.ctrlKey || e.altKey || e.metaKey || e.isComposing) return;
    if (e.key === 'Escape' && this.on) this.set(false);
    else if ((e.key === 'p' || e.key === 'P' || e.code === 'KeyP') && !typesText(e.target)) this.set(!this.on);
    else return;
    e.preventDefault();
    e.stopPropagation();
  }
}
