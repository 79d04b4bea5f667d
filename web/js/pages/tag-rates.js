// How well each action of a tag goes, for a caretaker: one line per action with its success
// rate, coloured by how good it is, over every kind of robot that tried it.

import { h } from '../dom.js';
import { grade, percent } from '../format.js';

/** The stats' groups (one per action and robot class) summed up per action. */
function perAction(groups) {
  const byAction = new Map();
  for (const group of groups) {
    const sum = byAction.get(group.action) ?? { attempts: 0, successes: 0, reliable: false };
    sum.attempts += group.attempts;
    sum.successes += Math.round((group.success_rate ?? 0) * group.attempts);
    sum.reliable ||= group.reliable;
    byAction.set(group.action, sum);
  }
  return [...byAction].map(([action, sum]) => ({ action, ...sum, rate: sum.attempts ? sum.successes / sum.attempts : null }));
}

/** The summary for the `groups` of GET /api/v1/tags/{epc}/stats; `actionTitle` names an action. */
export function successRates(groups, actionTitle) {
  const rows = perAction(groups);
  if (rows.length === 0) return h('p', { class: 'muted' }, 'No robot has tried it yet, so there is no success rate.');
  return h('ul', { class: 'rates' }, rows.map((row) => {
    const tries = `${row.attempts} ${row.attempts === 1 ? 'try' : 'tries'}`;
    const bar = h('span', { class: ['rate-bar', grade(row.rate)] });
    // Through the CSSOM: the Content-Security-Policy allows no inline style attributes.
    bar.style.width = `${Math.round((row.rate ?? 0) * 100)}%`;
    return h('li', { dataset: { action: row.action } },
      h('span', { class: 'rate-action' }, actionTitle(row.action)),
      h('span', { class: ['badge', 'rate', grade(row.rate)], dataset: { grade: grade(row.rate) } }, percent(row.rate)),
      h('span', { class: 'muted' }, ` of ${tries}${row.reliable ? ', reliable' : ''}`),
      h('span', { class: 'rate-track', 'aria-hidden': 'true' }, bar));
  }));
}
