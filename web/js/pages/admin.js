// For admins: the logins of the web UI, the robots, and the API tokens robots and scripts use.
// A new token's secret is shown once, right after it is made.

import { getAll, request, seg } from '../api.js';
import { askPassword, confirmDialog } from '../dialog.js';
import { cell, field, h, replace, uid } from '../dom.js';
import { when } from '../format.js';
import { loadSchemas, titlesFrom } from '../schema.js';
import * as session from '../session.js';

function select(options) {
  return h('select', {}, options.map(([value, label]) => h('option', { value }, label)));
}

/** The error of a failed request as one line, naming fields when the registry did. */
const problemText = (error) => (error.errors?.length ? error.errors.map((e) => e.message).join(' ') : error.message);

async function usersSection() {
  const list = h('div');
  const status = h('p', { class: 'status', role: 'status', 'aria-live': 'polite' });
  const show = async () => {
    const users = await getAll('/api/v1/users?limit=500');
    replace(list, h('table', { class: 'users responsive' },
      h('thead', {}, h('tr', {}, ['User', 'Role', 'Created', 'Password changed', ''].map((label) => h('th', { scope: 'col' }, label)))),
      h('tbody', {}, users.map((user) => {
        const isMe = user.name === session.user()?.name;
        const remove = isMe ? null : h('button', {
          type: 'button', class: 'link danger', 'aria-label': `Delete user ${user.name}`,
          on: {
            click: async () => {
              if (!await confirmDialog({ title: `Delete ${user.name}?`, message: `${user.name} will no longer be able to log in; their open sessions end now.`, confirm: 'Delete' })) return;
              try {
                await request('DELETE', `/api/v1/users/${seg(user.name)}`);
                status.textContent = `Deleted ${user.name}.`;
                show();
              } catch (error) {
                status.textContent = problemText(error);
              }
            },
          },
        }, 'Delete');
        const reset = h('button', {
          type: 'button', class: 'link', 'aria-label': `Set a new password for ${user.name}`,
          on: {
            click: async () => {
              const password = await askPassword({ title: `New password for ${user.name}`, help: 'At least 8 characters. Their open sessions end.' });
              if (!password) return;
              try {
                await request('PUT', `/api/v1/users/${seg(user.name)}/password`, { body: { password } });
                status.textContent = `Password of ${user.name} changed; their other sessions ended.`;
              } catch (error) {
                status.textContent = problemText(error);
              }
            },
          },
        }, 'Set password');
        return h('tr', { dataset: { user: user.name } },
          h('th', { scope: 'row', dataset: { label: 'User' } }, user.name, isMe ? h('span', { class: 'badge' }, 'you') : null),
          cell('Role', user.role),
          cell('Created', when(user.created_at)),
          cell('Password changed', when(user.password_changed_at)),
          h('td', { class: 'row-actions' }, reset, remove));
      }))));
  };
  const name = field({ label: 'User name', control: h('input', { type: 'text', autocomplete: 'off', autocapitalize: 'none', name: 'new-user-name' }), help: 'Letters a–z, digits, “.”, “_” and “-”.' });
  const role = field({ label: 'Role', control: select([['caretaker', 'caretaker: edits tags'], ['admin', 'admin: also users and tokens']]) });
  const password = field({ label: 'Password', control: h('input', { type: 'password', autocomplete: 'new-password', name: 'new-user-password' }), help: 'At least 8 characters; tell it to them in person.' });
  const form = h('form', { class: 'inline-form', novalidate: true }, name.wrapper, role.wrapper, password.wrapper,
    h('button', { type: 'submit', class: 'primary' }, 'Add user'));
  form.addEventListener('submit', async (event) => {
    event.preventDefault();
    try {
      const { data } = await request('POST', '/api/v1/users', { body: { name: name.control.value, role: role.control.value, password: password.control.value } });
      status.textContent = `Added ${data.name} (${data.role}).`;
      form.reset();
      show();
    } catch (error) {
      status.textContent = `Not added: ${problemText(error)}`;
    }
  });
  await show();
  return h('section', { 'aria-labelledby': 'users-h' }, h('h2', { id: 'users-h' }, 'Users'),
    h('p', { class: 'help' }, 'People who log in here.'), list, h('h3', {}, 'Add a user'), form, status);
}

/** Shows a robot token once, with what to do with it. */
function showSecret(into, title, token) {
  const secret = h('input', { type: 'text', readOnly: true, value: token, class: 'secret', 'aria-label': 'The new token' });
  secret.addEventListener('focus', () => secret.select());
  replace(into, h('div', { class: 'banner' },
    h('p', {}, h('strong', {}, title), ' It is shown only now: copy it into the robot.'),
    secret));
  secret.focus();
}

async function robotsSection() {
  // What a robot can do, named and titled by the tag schema, as on every other page.
  const schemas = await loadSchemas();
  const { behavior } = titlesFrom(schemas);
  const status = h('p', { class: 'status', role: 'status', 'aria-live': 'polite' });
  const minted = h('div', { 'aria-live': 'polite', id: 'robot-token' });
  const id = field({ label: 'Robot id', control: h('input', { type: 'text', autocomplete: 'off', autocapitalize: 'none', name: 'robot-id' }), help: 'How the robot names itself, e.g. stretch-2: letters, digits, “.”, “_” and “-”.' });
  const name = field({ label: 'Name', control: h('input', { type: 'text', autocomplete: 'off', name: 'robot-name' }), help: 'A name people recognise, e.g. “Kitchen Stretch”. Leave empty to use the id.' });
  const kind = field({ label: 'Class', control: h('input', { type: 'text', autocomplete: 'off', autocapitalize: 'none', name: 'robot-class' }), help: 'The kind of robot, e.g. stretch or el-e: robots of a class learn together.' });
  const abilities = schemas.behaviorNames.map((value) => {
    const box = h('input', { type: 'checkbox', id: uid('can'), name: 'capability', value, checked: true });
    return { value, box, wrapper: h('div', { class: 'field checkbox' }, box, h('label', { for: box.id }, behavior(value))) };
  });
  const form = h('form', { class: 'add-robot', novalidate: true }, id.wrapper, name.wrapper, kind.wrapper,
    h('fieldset', { class: 'section' }, h('legend', {}, 'What it can do'), abilities.map((a) => a.wrapper)),
    h('button', { type: 'submit', class: 'primary' }, 'Add robot'));
  form.addEventListener('submit', async (event) => {
    event.preventDefault();
    const robot = id.control.value.trim();
    if (!robot) {
      status.textContent = 'Not added: give the robot an id, e.g. stretch-2.';
      id.control.focus();
      return;
    }
    const body = {
      id: robot,
      name: name.control.value.trim() || robot,
      class: kind.control.value.trim() || null,
      capabilities: abilities.filter((a) => a.box.checked).map((a) => a.value),
    };
    try {
      const known = await request('GET', `/api/v1/robots/${seg(robot)}`).then(() => true, (error) => (error.status === 404 ? false : Promise.reject(error)));
      if (known) {
        status.textContent = `Not added: a robot called ${robot} exists already; choose another id.`;
        return;
      }
      await request('PUT', `/api/v1/robots/${seg(robot)}`, { body });
      const { data } = await request('POST', '/api/v1/tokens', { body: { role: 'robot', name: robot } });
      showSecret(minted, `Added ${robot}. Its token:`, data.token);
      status.textContent = `Added ${robot}; give it the token above.`;
      form.reset();
    } catch (error) {
      status.textContent = `Not added: ${problemText(error)}`;
    }
  });
  return h('section', { 'aria-labelledby': 'robots-h' }, h('h2', { id: 'robots-h' }, 'Add a robot'),
    h('p', { class: 'help' }, 'A robot needs an entry here and a token to call the registry. The Robots page shows what each is doing.'),
    minted, form, status);
}

async function tokensSection() {
  const list = h('div');
  const status = h('p', { class: 'status', role: 'status', 'aria-live': 'polite' });
  const minted = h('div', { 'aria-live': 'polite' });
  const state = (token) => {
    if (token.revoked_at) return ['revoked', 'bad'];
    if (token.expires_at && new Date(token.expires_at) <= new Date()) return ['expired', 'warn'];
    return ['active', 'good'];
  };
  const show = async () => {
    const tokens = await getAll('/api/v1/tokens?limit=500');
    replace(list, h('table', { class: 'tokens responsive' },
      h('thead', {}, h('tr', {}, ['Name', 'Role', 'Id', 'Created', 'Expires', 'State', ''].map((label) => h('th', { scope: 'col' }, label)))),
      h('tbody', {}, tokens.map((token) => {
        const [label, tone] = state(token);
        const revoke = label === 'active' ? h('button', {
          type: 'button', class: 'link danger', 'aria-label': `Revoke token ${token.name}`,
          on: {
            click: async () => {
              if (!await confirmDialog({ title: `Revoke “${token.name}”?`, message: 'Whatever uses this token stops working within seconds.', confirm: 'Revoke' })) return;
              try {
                await request('DELETE', `/api/v1/tokens/${seg(token.id)}`);
                status.textContent = `Revoked ${token.name}.`;
                show();
              } catch (error) {
                status.textContent = problemText(error);
              }
            },
          },
        }, 'Revoke') : null;
        return h('tr', { dataset: { token: token.id } },
          h('th', { scope: 'row', dataset: { label: 'Name' } }, token.name),
          cell('Role', token.role),
          cell('Id', h('code', {}, token.id)),
          cell('Created', when(token.created_at)),
          cell('Expires', token.expires_at ? when(token.expires_at) : 'never'),
          cell('State', h('span', { class: ['badge', tone] }, label)),
          h('td', { class: 'row-actions' }, revoke));
      }))));
  };
  const role = field({ label: 'Role', control: select([['robot', 'robot: bound to one robot id'], ['caretaker', 'caretaker'], ['admin', 'admin']]) });
  const name = field({ label: 'Name', control: h('input', { type: 'text', autocomplete: 'off', name: 'token-name' }), help: 'Who holds it; for a robot token, the robot id it is bound to (e.g. el-e-1).' });
  const days = field({ label: 'Expires after', control: h('input', { type: 'text', inputMode: 'numeric', autocomplete: 'off', name: 'token-days' }), unit: 'days', help: 'Leave empty for a token that does not expire.' });
  const form = h('form', { class: 'inline-form', novalidate: true }, role.wrapper, name.wrapper, days.wrapper,
    h('button', { type: 'submit', class: 'primary' }, 'Create token'));
  form.addEventListener('submit', async (event) => {
    event.preventDefault();
    const body = { role: role.control.value, name: name.control.value.trim() };
    if (days.control.value.trim()) body.expires_in_days = Number(days.control.value.trim());
    try {
      const { data } = await request('POST', '/api/v1/tokens', { body });
      showSecret(minted, `Token for ${data.name} (${data.role}).`, data.token);
      status.textContent = '';
      form.reset();
      show();
    } catch (error) {
      status.textContent = `Not created: ${problemText(error)}`;
    }
  });
  await show();
  return h('section', { 'aria-labelledby': 'tokens-h' }, h('h2', { id: 'tokens-h' }, 'API tokens'),
    h('p', { class: 'help' }, 'Robots and scripts use tokens; they are stored only as hashes.'), minted, list, h('h3', {}, 'Create a token'), form, status);
}

/** Whether this server's Home Assistant bridge is connected, and how to turn it on. */
async function homeAssistantSection() {
  const { data } = await request('GET', '/api/v1/home-assistant');
  const said = {
    off: ['off', 'warn', 'Start the server with --mqtt mqtt://USER:PASS@HOST:1883 (the broker Home Assistant\'s MQTT integration uses), or mqtts://USER:PASS@HOST with --mqtt-ca CA.pem for TLS, to show every tag there.'],
    standby: ['standby', 'good', 'Another replica of this registry runs the bridge.'],
    connecting: ['connecting', 'bad', `Cannot use the broker ${data.broker ?? ''} now${data.problem ? `: ${data.problem}` : ''}. The bridge keeps trying, and the registry works on meanwhile.`],
    connected: ['connected', 'good', `Tags appear in Home Assistant through ${data.broker ?? ''} (discovery prefix ${data.prefix ?? ''}).`],
  }[data.bridge] ?? [data.bridge, 'warn', ''];
  const [label, tone, help] = said;
  return h('section', { 'aria-labelledby': 'ha-h' }, h('h2', { id: 'ha-h' }, 'Home Assistant'),
    h('p', {}, 'Bridge: ', h('span', { class: ['badge', tone], dataset: { bridge: data.bridge } }, label)),
    h('p', { class: 'help' }, help, ' Presses there are asked as the caretaker token “Home Assistant bridge”; revoke it below to refuse them.'));
}

export async function render(main) {
  document.title = 'Admin · PPS-tag registry';
  const guarded = async (build, title) => {
    try {
      return await build();
    } catch (error) {
      return h('section', {}, h('h2', {}, title), h('p', { class: 'status bad' }, `Could not load: ${error.message}`));
    }
  };
  const [users, robots, tokens, bridge] = await Promise.all([
    guarded(usersSection, 'Users'), guarded(robotsSection, 'Robots'), guarded(tokensSection, 'API tokens'),
    guarded(homeAssistantSection, 'Home Assistant'),
  ]);
  replace(main, h('h1', {}, 'Admin'), users, robots, tokens, bridge);
}
