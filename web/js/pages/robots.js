// The robots the registry knows: which are on now (seen within the last minute), what each is
// doing, what waits for whom, and class, capabilities, limits (live).

import { getAll, seg } from '../api.js';
import { cell, debounce, h, replace } from '../dom.js';
import { subscribe } from '../events.js';
import { ago } from '../format.js';
import { loadSchemas, titlesFrom } from '../schema.js';
import { eitherOf, forWhom, stuckReason } from '../tasks.js';

/** A robot seen within this long is on: a working robot asks for work far more often. */
const ONLINE_MS = 60000;
/** How often the page looks again: being on is a matter of time, not of events. */
const RECHECK_MS = 15000;

function online(robot) {
  return Boolean(robot.last_seen) && Date.now() - new Date(robot.last_seen).getTime() <= ONLINE_MS;
}

/** A task as a caretaker says it: "Turn off on Bedside lamp". */
function what(task, labels) {
  return [h('strong', {}, labels.action(task.action)), ' on ', h('a', { href: `#/tags/${seg(task.epc)}` }, labels.tag(task.epc))];
}

/** What the robot is doing now: the task it holds, the one it is about to take, or why none. */
function doing(robot, held, waiting, labels) {
  const task = held.get(robot.id);
  if (task) return h('span', {}, ...what(task, labels));
  const next = waiting.find((t) => (t.waiting_for ?? []).includes(robot.id));
  if (next) return h('span', {}, 'about to take ', ...what(next, labels));
  if (online(robot)) return h('span', { class: 'muted' }, 'free: nothing it can do is waiting');
  return h('span', { class: 'muted' }, 'off');
}

/** The tasks waiting for a robot, each with whom it waits for or why none will take it. */
function waitingList(waiting, labels) {
  if (waiting.length === 0) return h('p', { class: 'muted', id: 'waiting' }, 'Nothing is waiting for a robot.');
  return h('ul', { class: 'waiting', id: 'waiting' }, waiting.map((task) => {
    const stuck = stuckReason(task);
    return h('li', { dataset: { task: task.id } }, ...what(task, labels), h('span', { class: 'muted' }, ` (for ${forWhom(task)})`), ': ',
      stuck
        ? h('span', { class: 'stuck-inline' }, h('strong', {}, 'no robot can take it now'), ` (${stuck})`)
        : `waits for ${eitherOf(task.waiting_for ?? []) || 'a robot'}`);
  }));
}

export async function render(main) {
  document.title = 'Robots · PPS-tag registry';
  const box = h('div');
  const tags = await getAll('/api/v1/tags?limit=500', { maxPages: 4 }).catch(() => []);
  const tagNames = new Map(tags.map((t) => [t.epc, t.properties?.name || t.epc]));
  const labels = { tag: (epc) => tagNames.get(epc) ?? epc, ...titlesFrom(await loadSchemas()) };
  const show = async () => {
    const robots = await getAll('/api/v1/robots?limit=500');
    const claimed = await getAll('/api/v1/tasks?state=claimed&limit=500', { maxPages: 1 }).catch(() => []);
    const waiting = await getAll('/api/v1/tasks?state=queued&limit=200', { maxPages: 1 }).catch(() => []);
    const held = new Map(claimed.map((task) => [task.claimed_by, task]));
    const on = robots.filter(online).length;
    replace(box,
      h('h2', {}, 'Waiting for a robot'),
      waitingList(waiting, labels),
      h('h2', {}, 'Robots'),
      robots.length === 0
        ? h('p', { class: 'muted' }, 'No robots yet. An admin adds one on the Admin page; a robot with a token shows up when it first calls the registry.')
        : h('p', { class: 'help', id: 'robots-on' }, `${on} of ${robots.length} on now (seen in the last minute).`),
      robots.length === 0 ? null : h('table', { class: 'robots responsive' },
        h('thead', {}, h('tr', {}, ['Robot', 'On now', 'Doing now', 'Class', 'Capabilities', 'Max force', 'Last seen'].map((label) => h('th', { scope: 'col' }, label)))),
        h('tbody', {}, robots.map((robot) => h('tr', { dataset: { robot: robot.id, online: online(robot) ? 'yes' : 'no' } },
          h('th', { scope: 'row', dataset: { label: 'Robot' } }, robot.name ?? robot.id, h('div', { class: 'muted' }, h('code', {}, robot.id))),
          cell('On now', online(robot) ? h('span', { class: 'badge good' }, 'on') : h('span', { class: 'badge' }, 'off')),
          cell('Doing now', doing(robot, held, waiting, labels)),
          cell('Class', robot.class ?? 'not set'),
          cell('Capabilities', (robot.capabilities ?? []).length
            ? h('ul', { class: 'chips' }, robot.capabilities.map((c) => h('li', { dataset: { capability: c } }, labels.behavior(c)))) : '—'),
          cell('Max force', typeof robot.limits?.max_force === 'number' ? `${robot.limits.max_force} N` : '—'),
          cell('Last seen', ago(robot.last_seen)))))));
  };
  replace(main, h('h1', {}, 'Robots'), box);
  await show();
  const changed = debounce(() => show().catch(() => {}), 150);
  const unsubscribe = subscribe((type) => {
    if (type === 'robot_changed' || type === 'task_changed') changed();
  });
  const every = setInterval(changed, RECHECK_MS);
  return () => {
    clearInterval(every);
    unsubscribe();
  };
}
