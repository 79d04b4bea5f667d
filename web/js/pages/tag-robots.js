// What one robot gets for a tag: the merged entry's values that do not come from the base entry
// (learned, or a robot class's or one robot's override) with their provenance, and the actions
// the robot cannot do, with the reason.

import { get, seg } from '../api.js';
import { cell, h, replace, uid } from '../dom.js';
import { fieldPath, short } from '../format.js';
import { getAt } from '../pointer.js';

/**
 * The per-robot view of one tag in `container`, as a function that shows it again. The first
 * call lists the robots; later calls (after the entry or its learned values changed) keep the
 * robot chosen and fetch what it gets now.
 */
export function robotView(container, epc) {
  let show = null;
  return async () => {
    if (show) return show();
    const { items: robots = [] } = await get('/api/v1/robots?limit=500');
    if (robots.length === 0) {
      replace(container, h('p', { class: 'muted' }, 'No robots are registered yet.'));
      return;
    }
    const id = uid('robot');
    const select = h('select', { id }, robots.map((robot) => h('option', { value: robot.id }, `${robot.name ?? robot.id} (${robot.id})`)));
    const result = h('div', { 'aria-live': 'polite' });
    show = () => showEffective(result, select.value, epc);
    select.addEventListener('change', show);
    replace(container, h('div', { class: 'field' }, h('label', { for: id }, 'Robot'), select), result);
    await show();
  };
}

async function showEffective(result, robot, epc) {
  try {
    const effective = await get(`/api/v1/robots/${seg(robot)}/tags/${seg(epc)}`);
    const overridden = Object.entries(effective.provenance ?? {}).filter(([, source]) => source !== 'base');
    replace(result,
      overridden.length === 0
        ? h('p', {}, 'This robot uses the entry as it is: no learned values or overrides.')
        : h('table', { class: 'responsive' },
          h('thead', {}, h('tr', {}, ['Field', 'Value', 'From'].map((label) => h('th', { scope: 'col' }, label)))),
          h('tbody', {}, overridden.map(([pointer, source]) => h('tr', { dataset: { pointer } },
            h('th', { scope: 'row', dataset: { label: 'Field' } }, fieldPath(pointer)),
            cell('Value', h('code', {}, short(getAt(effective.entry, pointer)))),
            cell('From', h('span', { class: 'badge' }, source)))))),
      (effective.unavailable_actions ?? []).length
        ? h('div', {}, h('h3', {}, 'Actions this robot cannot do'),
          h('ul', {}, effective.unavailable_actions.map((u) => h('li', {}, h('strong', {}, u.action), ` (${u.behavior}): ${u.reason}`))))
        : null);
  } catch (error) {
    replace(result, h('p', { class: 'status bad' }, error.message));
  }
}
