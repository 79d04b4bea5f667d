// A user's own account: change the password (the current one is needed).

import { request, seg } from '../api.js';
import { field, h, replace } from '../dom.js';
import * as session from '../session.js';

export async function render(main) {
  document.title = 'Your account · PPS-tag registry';
  const user = session.user();
  if (user.credential !== 'session') {
    replace(main, h('h1', {}, 'Your account'), h('p', {}, 'You are using an API token, which has no password.'));
    return;
  }
  const current = field({ label: 'Current password', control: h('input', { type: 'password', autocomplete: 'current-password', name: 'current-password' }) });
  const next = field({ label: 'New password', control: h('input', { type: 'password', autocomplete: 'new-password', name: 'new-password' }), help: 'At least 8 characters. Your other sessions end when you change it.' });
  const again = field({ label: 'New password again', control: h('input', { type: 'password', autocomplete: 'new-password', name: 'new-password-again' }) });
  const status = h('p', { class: 'status', role: 'status', 'aria-live': 'polite' });
  const form = h('form', { class: 'narrow', novalidate: true }, current.wrapper, next.wrapper, again.wrapper,
    h('button', { type: 'submit', class: 'primary' }, 'Change password'), status);
  form.addEventListener('submit', async (event) => {
    event.preventDefault();
    status.classList.add('bad');
    if (next.control.value !== again.control.value) {
      status.textContent = 'The two new passwords differ.';
      return;
    }
    try {
      await request('PUT', `/api/v1/users/${seg(user.name)}/password`, {
        body: { password: next.control.value, current_password: current.control.value },
      });
      status.classList.remove('bad');
      status.textContent = 'Password changed.';
      form.reset();
    } catch (error) {
      status.textContent = error.errors.length ? error.errors.map((e) => e.message).join(' ') : error.message;
    }
  });
  replace(main, h('h1', {}, 'Your account'),
    h('p', {}, `Logged in as ${user.name} (${user.role}); this session ends ${new Date(user.expires_at).toLocaleString()}.`),
    h('h2', {}, 'Change your password'), form);
}
