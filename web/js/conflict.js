// What a caretaker sees when someone else saved the tag first (412): the fields each side
// changed since the revision they started from, and the two ways on. Nothing is overwritten
// until they choose and save again.

import { threeWay } from './diff.js';
import { cell, h } from './dom.js';
import { fieldPath, short, when } from './format.js';

/**
 * A panel comparing `base` (the revision the caretaker edited), `theirs` (the tag as now
 * stored) and `mine`; `onReload()` takes theirs, `onReapply()` puts mine on top of theirs.
 */
export function conflictPanel({ base, baseRevision, theirsTag, theirs, mine, onReload, onReapply }) {
  const rows = threeWay(base, theirs, mine);
  const heading = h('h2', { tabindex: '-1' }, 'Someone else saved this tag first');
  const same = (a, b) => JSON.stringify(a) === JSON.stringify(b);
  const value = (v, label, changed) => {
    const td = cell(label, h('code', {}, short(v)));
    if (changed) td.classList.add('changed');
    return td;
  };
  const panel = h('section', { class: 'conflict', role: 'region', 'aria-label': 'Edit conflict' },
    heading,
    h('p', {},
      `${theirsTag.updated_by ?? 'Someone'} saved revision ${theirsTag.revision} at ${when(theirsTag.updated_at)} `,
      `while you were editing revision ${baseRevision}. Nothing was overwritten. What changed:`),
    rows.length === 0
      ? h('p', {}, 'Their revision changes nothing you see here (perhaps it was archived or restored).')
      : h('table', { class: 'diff responsive' },
        h('thead', {}, h('tr', {},
          h('th', { scope: 'col' }, 'Field'),
          h('th', { scope: 'col' }, `Revision ${baseRevision} (you started from)`),
          h('th', { scope: 'col' }, `Theirs (revision ${theirsTag.revision})`),
          h('th', { scope: 'col' }, 'Yours'))),
        h('tbody', {}, rows.map((row) => h('tr', { class: row.conflict ? 'both-changed' : null, dataset: { pointer: row.pointer } },
          h('th', { scope: 'row' }, fieldPath(row.pointer), row.conflict ? h('span', { class: 'badge warn' }, 'both changed') : null),
          value(row.base, `Revision ${baseRevision}`, false),
          value(row.theirs, 'Theirs', !same(row.theirs, row.base)),
          value(row.mine, 'Yours', !same(row.mine, row.base)))))),
    h('div', { class: 'actions' },
      h('button', { type: 'button', class: 'primary', on: { click: onReapply } }, 'Reapply my changes on theirs'),
      h('button', { type: 'button', class: 'secondary', on: { click: onReload } }, 'Discard mine and load theirs')),
    h('p', { class: 'help' }, 'Reapplying puts your changes on top of their version (yours win where both changed a field); review it, then save again.'));
  queueMicrotask(() => heading.focus());
  return panel;
}
