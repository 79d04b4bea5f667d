// The robots the registry knows: class, capabilities, limits and when each was last seen.

import { getAll } from '../api.js';
import { cell, h, replace } from '../dom.js';
import { subscribe } from '../events.js';
import { ago } from '../format.js';

export async function render(main) {
  document.title = 'Robots · PPS-tag registry';
  const box = h('div');
  const show = async () => {
    const robots = await getAll('/api/v1/robots?limit=500');
    replace(box, robots.length === 0
      ? h('p', { class: 'muted' }, 'No robots yet. An admin registers one with PUT /api/v1/robots/{id}; a robot with a token shows up when it first calls the registry.')
      : h('table', { class: 'robots responsive' },
        h('thead', {}, h('tr', {}, ['Robot', 'Class', 'Capabilities', 'Max force', 'Last seen'].map((label) => h('th', { scope: 'col' }, label)))),
        h('tbody', {}, robots.map((robot) => h('tr', { dataset: { robot: robot.id } },
          h('th', { scope: 'row', dataset: { label: 'Robot' } }, robot.name ?? robot.id, h('div', { class: 'muted' }, h('code', {}, robot.id))),
          cell('Class', robot.class ?? 'not set'),
          cell('Capabilities', (robot.capabilities ?? []).length
            ? h('ul', { class: 'chips' }, robot.capabilities.map((c) => h('li', {}, c))) : '—'),
          cell('Max force', typeof robot.limits?.max_force === 'number' ? `${robot.limits.max_force} N` : '—'),
          cell('Last seen', ago(robot.last_seen)))))));
  };
  replace(main, h('h1', {}, 'Robots'), box);
  await show();
  return subscribe((type) => {
    if (type === 'robot_changed') show().catch(() => {});
  });
}
