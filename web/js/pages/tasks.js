// What caretakers asked robots to do, newest first, with how each stands (live), who holds it,
// who declined it and why, why a waiting task is stuck, the trial it ended in, and a way to
// cancel what has not ended.

import { getAll, query, seg } from '../api.js';
import { cell, debounce, h, replace, uid } from '../dom.js';
import { subscribe } from '../events.js';
import { ago, when } from '../format.js';
import { loadSchemas, titlesFrom } from '../schema.js';
import { cancel, expiryNote, forWhom, stateOf, stuckReason } from '../tasks.js';

/** How often waiting tasks are looked at again: a robot counts as on for a minute after it was seen. */
const ONLINE_CHECK_MS = 15000;

const STATES = [['', 'All'], ['queued', 'Waiting'], ['claimed', 'Being done'], ['done', 'Done'], ['failed', 'Failed'], ['cancelled', 'Cancelled']];

function taskRow(task, labels, refresh) {
  const name = labels.tag(task.epc);
  const action = labels.action(task.action);
  const { text, badge } = stateOf(task);
  const status = h('p', { class: 'status', role: 'status' });
  const open = ['queued', 'claimed'].includes(task.state);
  const stop = open
    ? h('button', {
      type: 'button', class: 'small danger', 'aria-label': `Cancel “${action}” on ${name}`,
      on: {
        click: async (event) => {
          event.target.disabled = true;
          try {
            await cancel(task);
            refresh();
          } catch (error) {
            status.classList.add('bad');
            status.textContent = error.message;
            event.target.disabled = false;
          }
        },
      },
    }, 'Cancel')
    : null;
  const stuck = stuckReason(task);
  const declines = (task.declined ?? []).length
    ? h('ul', { class: 'declines' }, task.declined.map((d) => declineItem(d, { reasonShown: Boolean(stuck) })))
    : null;
  const expiry = expiryNote(task);
  return h('tr', { dataset: { task: task.id, state: task.state, stuck: stuck ? 'yes' : 'no', expired: task.expired ? 'yes' : 'no' } },
    cell('Asked', when(task.created_at), h('div', { class: 'muted' }, `by ${task.created_by}`)),
    cell('Tag', h('a', { href: `#/tags/${seg(task.epc)}` }, name)),
    cell('Action', h('strong', {}, action), task.note ? h('div', { class: 'muted' }, task.note) : null),
    cell('For', forWhom(task)),
    cell('State', h('span', { class: ['badge', badge] }, text),
      stuck ? h('p', { class: 'stuck' }, h('strong', {}, 'Why it waits: '), stuck, '. It stays waiting until a robot can take it; cancel it if it is no longer wanted.') : null,
      declines,
      task.expired ? h('p', { class: 'expired' }, expiry) : null,
      task.reason && !task.expired ? h('div', { class: 'muted' }, task.reason) : null,
      expiry && !task.expired ? h('div', { class: 'muted' }, expiry) : null,
      task.attempts > 1 ? h('div', { class: 'muted' }, `attempt ${task.attempts}`) : null),
    cell('Trial', task.trial ? h('a', { href: `#/tags/${seg(task.epc)}`, dataset: { trial: task.trial } }, `trial ${task.trial.slice(0, 8)}`) : '—'),
    cell('Cancel', stop, status));
}

/**
 * One robot's decline: who, when and why, in a caretaker's words; what the robot itself said
 * opens on request. A waiting task's red note already gives every reason, so there the line
 * says only who declined and when.
 */
function declineItem(decline, { reasonShown }) {
  return h('li', { dataset: { robot: decline.robot } },
    h('strong', {}, `${decline.robot} declined`),
    reasonShown ? null : `: ${decline.reason}`,
    h('span', { class: 'muted' }, ` (${ago(decline.at)})`),
    decline.detail
      ? h('details', { class: 'robot-words' }, h('summary', {}, 'What the robot said'), h('p', { class: 'muted' }, decline.detail))
      : null);
}

export async function render(main) {
  document.title = 'Tasks · PPS-tag registry';
  const filterId = uid('state');
  const filter = h('select', { id: filterId }, STATES.map(([value, label]) => h('option', { value }, label)));
  const box = h('div', { class: 'card' }, h('p', { class: 'muted' }, 'Loading…'));
  const tags = await getAll('/api/v1/tags?limit=500', { maxPages: 4 }).catch(() => []);
  const tagNames = new Map(tags.map((t) => [t.epc, t.properties?.name || t.epc]));
  const labels = { tag: (epc) => tagNames.get(epc) ?? epc, ...titlesFrom(await loadSchemas()) };
  const show = async () => {
    const tasks = await getAll(`/api/v1/tasks${query({ state: filter.value, limit: 200 })}`, { maxPages: 1 });
    replace(box, tasks.length === 0
      ? h('p', { class: 'muted' }, filter.value ? 'No tasks in this state.' : 'Nobody asked for anything yet. On a tag\'s page, “Ask a robot to …” does.')
      : h('table', { class: 'tasks responsive' },
        h('caption', { class: 'visually-hidden' }, 'Tasks, newest first'),
        h('thead', {}, h('tr', {}, ['Asked', 'Tag', 'Action', 'For', 'State', 'Trial', 'Cancel'].map((label) => h('th', { scope: 'col' }, label)))),
        h('tbody', {}, tasks.map((task) => taskRow(task, labels, () => show().catch(() => {}))))));
  };
  filter.addEventListener('change', () => show().catch(() => {}));
  replace(main, h('h1', {}, 'Tasks'),
    h('p', { class: 'help' }, 'What caretakers asked robots to do. A robot that cannot do a task says why and leaves it to the others; when no robot that is on can take it, the task says so here at once. A robot that stops answering loses its task after a while and another robot takes it; after three such attempts the task fails. A task nobody did in time (a day, unless asked otherwise) expires and says so.'),
    h('div', { class: 'field narrow' }, h('label', { for: filterId }, 'Show'), filter),
    box);
  await show();
  const changed = debounce(() => show().catch(() => {}), 150);
  const unsubscribe = subscribe((type) => {
    if (type === 'task_changed') changed();
  });
  // Robots going quiet changes what a waiting task can hope for without any event.
  const every = setInterval(changed, ONLINE_CHECK_MS);
  return () => {
    clearInterval(every);
    unsubscribe();
  };
}
