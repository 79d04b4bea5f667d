// Questions that must be answered before something hard to undo (archive, revoke, delete, a
// new password for someone). A native modal <dialog>: focus stays inside, Escape cancels.

import { field, h } from './dom.js';

/** Shows a modal with `content` and a confirm button; resolves with `answer()` or null. */
function ask({ title, content, confirm, answer, focus, tone = 'danger' }) {
  return new Promise((resolve) => {
    const cancelButton = h('button', { type: 'button', class: 'secondary' }, 'Cancel');
    const confirmButton = h('button', { type: 'submit', class: tone }, confirm);
    const form = h('form', { method: 'dialog' }, content, h('div', { class: 'actions' }, confirmButton, cancelButton));
    const dialog = h('dialog', { class: 'confirm', 'aria-labelledby': 'dialog-title' }, h('h2', { id: 'dialog-title' }, title), form);
    const finish = (result) => {
      dialog.close();
      dialog.remove();
      resolve(result);
    };
    cancelButton.addEventListener('click', () => finish(null));
    form.addEventListener('submit', (event) => {
      event.preventDefault();
      finish(answer());
    });
    dialog.addEventListener('cancel', (event) => {
      event.preventDefault();
      finish(null);
    });
    document.body.append(dialog);
    dialog.showModal();
    (focus ?? cancelButton).focus();
  });
}

/** Resolves true when the person confirms; the safe choice (Cancel) has the focus. */
export async function confirmDialog({ title, message, confirm }) {
  return (await ask({ title, content: h('p', {}, message), confirm, answer: () => true })) === true;
}

/** Asks for a new password (hidden as typed); resolves with it, or null when cancelled. */
export function askPassword({ title, help }) {
  const input = h('input', { type: 'password', autocomplete: 'new-password', name: 'dialog-password' });
  const { wrapper } = field({ label: 'New password', control: input, help });
  return ask({ title, content: wrapper, confirm: 'Set password', answer: () => input.value || null, focus: input, tone: 'primary' });
}
