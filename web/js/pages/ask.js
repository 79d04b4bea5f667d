// "Ask a robot to …" on a tag's page: one button per action opens a small form (who may do it,
// a note), and the answer follows the task live: waiting, being done by whom, done.

import { h, replace, uid } from '../dom.js';
import { subscribe } from '../events.js';
import { askFor, askLabel, stateOf } from '../tasks.js';

/** The choices of who may do it: any robot, a kind of robot, or one robot. */
function whoSelect(id, robots) {
  const classes = [...new Set(robots.map((r) => r.class).filter(Boolean))].sort();
  return h('select', { id, name: 'who' },
    h('option', { value: '' }, 'Any robot that can'),
    classes.length ? h('optgroup', { label: 'Any robot of a kind' }, classes.map((c) => h('option', { value: `class:${c}` }, `any ${c} robot`))) : null,
    robots.length ? h('optgroup', { label: 'One robot' }, robots.map((r) => h('option', { value: `robot:${r.id}` }, r.name && r.name !== r.id ? `${r.name} (${r.id})` : r.id))) : null);
}

/** The button and its form for one action of the tag; `stops` collects live subscriptions. */
export function askControl(tag, action, robots, stops) {
  const formId = uid('ask');
  const whoId = uid('who');
  const noteId = uid('note');
  const status = h('p', { class: 'status', role: 'status' });
  const who = whoSelect(whoId, robots);
  const note = h('input', { id: noteId, type: 'text', name: 'note', maxlength: '500', autocomplete: 'off' });
  const submit = h('button', { type: 'submit', class: 'primary' }, 'Ask');
  const form = h('form', { id: formId, class: 'ask-form', hidden: true, 'aria-label': askLabel(action) },
    h('div', { class: 'field' }, h('label', { for: whoId }, 'Who may do it'), who),
    h('div', { class: 'field' }, h('label', { for: noteId }, 'Note for the record (optional)'), note),
    h('div', { class: 'ask-buttons' }, submit,
      h('button', { type: 'button', class: 'secondary', on: { click: () => toggle(false) } }, 'Cancel')));
  const open = h('button', { type: 'button', class: 'secondary ask', 'aria-expanded': 'false', 'aria-controls': formId, dataset: { action } }, askLabel(action));
  const toggle = (show) => {
    form.hidden = !show;
    open.setAttribute('aria-expanded', String(show));
    if (show) who.focus();
    else open.focus();
  };
  open.addEventListener('click', () => toggle(form.hidden));
  form.addEventListener('submit', async (event) => {
    event.preventDefault();
    const [kind, name] = who.value ? who.value.split(':') : [];
    const body = { epc: tag.epc, action };
    if (kind === 'class') body.class = name;
    if (kind === 'robot') body.robot = name;
    if (note.value.trim()) body.note = note.value.trim();
    submit.disabled = true;
    try {
      const task = await askFor(body);
      toggle(false);
      follow(task, status, stops);
    } catch (error) {
      status.classList.add('bad');
      status.textContent = `Not asked: ${[error.message, ...error.errors?.map((e) => e.message) ?? []].join(' ')}`;
    } finally {
      submit.disabled = false;
    }
  });
  return h('div', { class: 'ask-control' }, open, form, status);
}

/** Shows how the asked task stands, live, until it ends. */
function follow(task, status, stops) {
  const show = (t) => {
    status.classList.toggle('bad', t.state === 'failed');
    const { text } = stateOf(t);
    replace(status, `Asked: ${text}.`, ' ', h('a', { href: '#/tasks' }, 'All tasks'));
  };
  show(task);
  const stop = subscribe((type, data) => {
    if (type !== 'task_changed' || data.task !== task.id) return;
    show({ ...task, ...data, state: data.state, claimed_by: data.claimed_by });
    if (!['queued', 'claimed'].includes(data.state)) stop();
  });
  stops.push(stop);
}
