// The login form: what a visitor who is not logged in sees at /.

import { h, replace } from '../dom.js';
import * as session from '../session.js';

/** Shows the login form in `root`; `onLoggedIn()` runs after a successful login. */
export function renderLogin(root, { message, onLoggedIn }) {
  const username = h('input', {
    id: 'login-username', name: 'username', type: 'text', autocomplete: 'username',
    autocapitalize: 'none', spellcheck: false, required: true,
  });
  const password = h('input', {
    id: 'login-password', name: 'password', type: 'password', autocomplete: 'current-password', required: true,
  });
  const status = h('p', { class: 'status', role: 'alert', 'aria-live': 'assertive' }, message ?? '');
  const submit = h('button', { type: 'submit', class: 'primary' }, 'Log in');
  const form = h('form', { class: 'login-form', novalidate: true },
    h('div', { class: 'field' }, h('label', { for: username.id }, 'User name'), username),
    h('div', { class: 'field' }, h('label', { for: password.id }, 'Password'), password),
    submit, status);
  form.addEventListener('submit', async (event) => {
    event.preventDefault();
    if (!username.value.trim() || !password.value) {
      status.textContent = 'Enter your user name and password.';
      status.classList.add('bad');
      return;
    }
    submit.disabled = true;
    status.classList.remove('bad');
    status.textContent = 'Logging in…';
    try {
      await session.login(username.value, password.value);
      onLoggedIn();
    } catch (error) {
      status.classList.add('bad');
      if (error.status === 401) status.textContent = 'Wrong user name or password.';
      else if (error.status === 429) status.textContent = `Too many wrong passwords. ${error.problem.detail ?? 'Wait a moment and try again.'}`;
      else status.textContent = `Could not log in: ${error.message}`;
      password.select();
    } finally {
      submit.disabled = false;
    }
  });
  replace(root, h('main', { id: 'main', class: 'page login-page' },
    h('div', { class: 'login-card' },
      h('h1', {}, h('span', { class: 'brand-mark', 'aria-hidden': 'true' }), 'PPS-tag registry'),
      h('p', { class: 'muted' }, 'Log in to register tags and see what the robots did with them.'),
      form,
      h('p', { class: 'help' }, 'No login yet? An administrator makes one with ',
        h('code', {}, 'pps-server user add NAME --role caretaker'), ' or on the Admin page.'))));
  username.focus();
}
