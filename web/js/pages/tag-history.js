// Who changed what on a tag: every revision, newest first, with the fields it changed.

import { getAll, seg } from '../api.js';
import { changes } from '../diff.js';
import { h, replace } from '../dom.js';
import { fieldPath, short, when } from '../format.js';

/** How many changed fields one revision lists before "and N more". */
const SHOWN_CHANGES = 12;

export async function renderHistory(container, epc) {
  const revisions = await getAll(`/api/v1/tags/${seg(epc)}/revisions?limit=500`);
  const items = revisions.map((revision, i) => {
    const previous = i > 0 ? revisions[i - 1].entry : null;
    const changed = previous ? changes(previous, revision.entry) : [];
    const list = changed.slice(0, SHOWN_CHANGES).map((c) => h('li', {},
      h('span', { class: 'field-name' }, fieldPath(c.pointer)), ': ',
      h('code', {}, short(c.before)), ' → ', h('code', {}, short(c.after))));
    if (changed.length > SHOWN_CHANGES) list.push(h('li', { class: 'muted' }, `and ${changed.length - SHOWN_CHANGES} more`));
    return h('li', { class: 'revision', dataset: { revision: revision.revision } },
      h('div', {}, h('strong', {}, `Revision ${revision.revision}`), ` · ${revision.change} by `,
        h('span', { class: 'who-changed' }, revision.changed_by), ` · ${when(revision.changed_at)}`),
      list.length ? h('ul', { class: 'changes' }, list) : null);
  });
  replace(container, h('ol', { class: 'history', reversed: true }, items.reverse()));
}
