// The robots the registry knows: class, capabilities, limits, when each was last seen and the
// task each is doing now (live).

import { getAll, seg } from '../api.js';
import { cell, debounce, h, replace } from '../dom.js';
import { subscribe } from '../events.js';
import { ago } from '../format.js';

/** What the robot is doing now: the task it holds, or nothing. */
function doing(task, names) {
  if (!task) return h('span', { class: 'muted' }, 'nothing asked');
  return h('span', {}, h('strong', {}, task.action), ' on ', h('a', { href: `#/tags/${seg(task.epc)}` }, names.get(task.epc) ?? task.epc));
}

export async function render(main) {
  document.title = 'Robots · PPS-tag registry';
  const box = h('div');
  const tags = await getAll('/api/v1/tags?limit=500', { maxPages: 4 }).catch(() => []);
  const names = new Map(tags.map((t) => [t.epc, t.properties?.name || t.epc]));
  const show = async () => {
    const robots = await getAll('/api/v1/robots?limit=500');
    const held = await getAll('/api/v1/tasks?state=claimed&limit=500', { maxPages: 1 }).catch(() => []);
    const holding = new Map(held.map((task) => [task.claimed_by, task]));
    replace(box, robots.length === 0
      ? h('p', { class: 'muted' }, 'No robots yet. An admin registers one with PUT /api/v1/robots/{id}; a robot with a token shows up when it first calls the registry.')
      : h('table', { class: 'robots responsive' },
        h('thead', {}, h('tr', {}, ['Robot', 'Class', 'Doing now', 'Capabilities', 'Max force', 'Last seen'].map((label) => h('th', { scope: 'col' }, label)))),
        h('tbody', {}, robots.map((robot) => h('tr', { dataset: { robot: robot.id } },
          h('th', { scope: 'row', dataset: { label: 'Robot' } }, robot.name ?? robot.id, h('div', { class: 'muted' }, h('code', {}, robot.id))),
          cell('Class', robot.class ?? 'not set'),
          cell('Doing now', doing(holding.get(robot.id), names)),
          cell('Capabilities', (robot.capabilities ?? []).length
            ? h('ul', { class: 'chips' }, robot.capabilities.map((c) => h('li', {}, c))) : '—'),
          cell('Max force', typeof robot.limits?.max_force === 'number' ? `${robot.limits.max_force} N` : '—'),
          cell('Last seen', ago(robot.last_seen)))))));
  };
  replace(main, h('h1', {}, 'Robots'), box);
  await show();
  const changed = debounce(() => show().catch(() => {}), 150);
  return subscribe((type) => {
    if (type === 'robot_changed' || type === 'task_changed') changed();
  });
}
