// One tag, followed: what it is, how each action went (a chart), what was learned, what each
// robot gets, every trial and every change. Trials appear as robots record them (live feed).
// From here a caretaker edits, archives or restores the tag, or moves it to a new EPC.

import { entryOf, etagOf, get, getAll, query, request, seg } from '../api.js';
import { successChart } from '../chart.js';
import { confirmDialog } from '../dialog.js';
import { debounce, h, replace, uid } from '../dom.js';
import { mountEditor } from '../editor.js';
import { subscribe } from '../events.js';
import { when } from '../format.js';
import { learnedInWords } from '../learned.js';
import { countedControl, countedInWords, noCountedTrials } from '../purpose.js';
import { askControl } from './ask.js';
import { renderHistory } from './tag-history.js';
import { renderRobotView } from './tag-robots.js';
import { renderTrials } from './tag-trials.js';

/** Runs a section's loader, showing its failure in the section rather than failing the page. */
async function section(container, load) {
  try {
    await load();
  } catch (error) {
    replace(container, h('p', { class: 'status bad' }, `Could not load this part: ${error.message}`));
  }
}

function header(tag, { onArchive, onRestore, robots, stops }) {
  const p = tag.properties ?? {};
  return h('div', { class: 'tag-head' },
    h('div', { class: 'page-head' },
      h('h1', { class: 'tag-title' }, p.name || '(no name)'),
      h('div', { class: 'actions' },
        tag.archived
          ? h('button', { type: 'button', class: 'primary', on: { click: onRestore } }, 'Restore')
          : h('a', { class: 'button primary', href: `#/tags/${seg(tag.epc)}/edit` }, 'Edit'),
        tag.archived ? null : h('button', { type: 'button', class: 'danger', on: { click: onArchive } }, 'Archive'))),
    tag.archived ? h('p', { class: 'banner' }, 'This tag is archived: robots no longer get it. Its trials are kept; restore it to use it again.') : null,
    h('dl', { class: 'facts' },
      h('dt', {}, 'Type'), h('dd', {}, p.type ?? '—'),
      h('dt', {}, 'Room'), h('dd', {}, p.location?.room ?? '—'),
      h('dt', {}, 'EPC'), h('dd', {}, h('code', { class: 'epc' }, tag.epc), tag.epc_uri ? h('div', { class: 'uri' }, tag.epc_uri) : null),
      h('dt', {}, 'Revision'), h('dd', {}, `${tag.revision}, saved by `, h('span', {}, tag.updated_by ?? '—'), ` · ${when(tag.updated_at)}`)),
    h('h2', {}, 'What robots can do'),
    h('ul', { class: 'action-list' }, Object.entries(tag.actions ?? {}).map(([action, key]) => {
      const spec = tag.behaviors?.[key] ?? {};
      return h('li', { dataset: { action } },
        h('div', {}, h('strong', {}, action), ` → ${key} `, h('span', { class: 'muted' }, `(${spec.behavior ?? 'unknown behaviour'})`)),
        tag.archived ? null : askControl(tag, action, robots, stops));
    })));
}

function statsView(stats) {
  const groups = stats.groups ?? [];
  const counted = h('p', { class: 'counted' }, countedInWords(stats));
  if (groups.length === 0) return h('div', {}, counted, h('p', { class: 'muted' }, noCountedTrials(stats)));
  // The registry lists under each action only what that action's behaviour uses.
  const learned = groups.filter((g) => Object.keys(g.learned ?? {}).length > 0);
  return h('div', {},
    counted,
    successChart(groups),
    h('p', { class: 'help' }, 'An action counts as reliable for a kind of robot after at least 20 attempts, at least 90 % of them successful (over its latest 50). A success is what the person confirmed, or else what the robot\'s own detector saw.'),
    h('h3', {}, 'Learned values'),
    learned.length === 0
      ? h('p', { class: 'muted' }, 'Nothing learned yet.')
      : h('ul', { class: 'learned' }, learned.map((g) => h('li', { dataset: { action: g.action } },
        h('strong', {}, g.action), `, ${g.robot_class ? `${g.robot_class} robots` : 'robots without a class'}: `,
        Object.entries(g.learned).map(([pointer, value]) => learnedInWords(pointer, value)).join('; ')))));
}

function retagForm(tag, inbox) {
  const id = uid('new-epc');
  const listId = uid('inbox-epcs');
  const input = h('input', { id, type: 'text', autocomplete: 'off', spellcheck: false, list: listId, required: true });
  const status = h('p', { class: 'status', role: 'status' });
  const form = h('form', { class: 'inline-form' },
    h('div', { class: 'field' }, h('label', { for: id }, 'New tag\'s EPC'), input,
      h('p', { class: 'help' }, 'When a worn tag is replaced: the entry, its history and learned values move to the new EPC.')),
    h('datalist', { id: listId }, inbox.map((item) => h('option', { value: item.epc }))),
    h('button', { type: 'submit', class: 'secondary' }, 'Move to new EPC'),
    status);
  form.addEventListener('submit', async (event) => {
    event.preventDefault();
    const newEpc = input.value.trim();
    if (!newEpc) return;
    const ok = await confirmDialog({
      title: 'Move this tag to a new EPC?',
      message: `“${tag.properties?.name ?? tag.epc}” will be found under ${newEpc} from now on; the old EPC ${tag.epc} stops working.`,
      confirm: 'Move it',
    });
    if (!ok) return;
    try {
      const { data } = await request('POST', `/api/v1/tags/${seg(tag.epc)}/retag`, { body: { new_epc: newEpc } });
      location.hash = `#/tags/${seg(data.epc ?? newEpc)}`;
    } catch (error) {
      status.textContent = `Not moved: ${error.message}`;
      status.classList.add('bad');
    }
  });
  return h('details', { class: 'retag' }, h('summary', {}, 'Replace a worn tag (retag)'), form);
}

export async function render(main, [epc]) {
  let tag = (await request('GET', `/api/v1/tags/${seg(epc)}`)).data;
  document.title = `${tag.properties?.name || tag.epc} · PPS-tag registry`;
  const notice = h('div', { 'aria-live': 'polite' });
  const head = h('div');
  const statsBox = h('div', { class: 'card' }, h('p', { class: 'muted' }, 'Loading…'));
  const trialsBox = h('div', { class: 'card', id: 'trials' }, h('p', { class: 'muted' }, 'Loading…'));
  const robotsBox = h('div', { class: 'card' }, h('p', { class: 'muted' }, 'Loading…'));
  const historyBox = h('div', { class: 'card' }, h('p', { class: 'muted' }, 'Loading…'));
  const retagBox = h('div');
  const robots = await getAll('/api/v1/robots?limit=500', { maxPages: 1 }).catch(() => []);
  const stops = [];
  const countedScope = countedControl(() => refreshTrials());

  const archive = async () => {
    const ok = await confirmDialog({
      title: 'Archive this tag?',
      message: `Robots will no longer get “${tag.properties?.name ?? tag.epc}”. Its trials and history are kept, and you can restore it later.`,
      confirm: 'Archive',
    });
    if (!ok) return;
    try {
      tag = (await request('DELETE', `/api/v1/tags/${seg(tag.epc)}`, { headers: { 'If-Match': etagOf(tag.revision) } })).data;
      showHead();
      replace(notice, h('p', { class: 'status' }, 'Archived.'));
    } catch (error) {
      replace(notice, h('p', { class: 'status bad', role: 'alert' },
        error.status === 412 ? 'Not archived: someone changed this tag meanwhile. The page now shows their version; check it and try again.' : `Not archived: ${error.message}`));
      if (error.status === 412) await refreshTag();
    }
  };
  const restore = async () => {
    try {
      tag = (await request('PUT', `/api/v1/tags/${seg(tag.epc)}`, { body: entryOf(tag), headers: { 'If-Match': etagOf(tag.revision) } })).data;
      showHead();
      replace(notice, h('p', { class: 'status' }, 'Restored.'));
    } catch (error) {
      replace(notice, h('p', { class: 'status bad', role: 'alert' }, `Not restored: ${error.message}`));
    }
  };
  const showHead = () => replace(head, header(tag, { onArchive: archive, onRestore: restore, robots, stops }));
  const refreshTag = async () => {
    tag = await get(`/api/v1/tags/${seg(tag.epc)}`);
    showHead();
    section(historyBox, () => renderHistory(historyBox, tag.epc));
  };
  const refreshTrials = () => {
    section(trialsBox, () => renderTrials(trialsBox, tag.epc));
    const include = query({ include: countedScope.include() });
    section(statsBox, async () => replace(statsBox, statsView(await get(`/api/v1/tags/${seg(tag.epc)}/stats${include}`))));
  };

  showHead();
  replace(main, notice, head,
    h('section', { 'aria-labelledby': 'success-h' }, h('h2', { id: 'success-h' }, 'Success per action'), countedScope.element, statsBox),
    h('section', { 'aria-labelledby': 'trials-h' }, h('h2', { id: 'trials-h' }, 'Trials'), trialsBox),
    h('section', { 'aria-labelledby': 'robots-h' }, h('h2', { id: 'robots-h' }, 'Per robot'),
      h('p', { class: 'help' }, 'What a robot gets when it reads this tag: values learned from its class\'s trials and per-robot overrides, and where each comes from.'), robotsBox),
    h('section', { 'aria-labelledby': 'history-h' }, h('h2', { id: 'history-h' }, 'History'), historyBox),
    retagBox);
  refreshTrials();
  section(robotsBox, () => renderRobotView(robotsBox, tag.epc));
  section(historyBox, () => renderHistory(historyBox, tag.epc));
  const inbox = await getAll('/api/v1/inbox?limit=100', { maxPages: 1 }).catch(() => []);
  if (!tag.archived) replace(retagBox, retagForm(tag, inbox));

  const trialsChanged = debounce(refreshTrials, 150);
  const tagChanged = debounce(refreshTag, 150);
  const learnedChanged = debounce(() => {
    refreshTrials();
    section(robotsBox, () => renderRobotView(robotsBox, tag.epc));
  }, 150);
  const unsubscribe = subscribe((type, data) => {
    if (data.epc !== tag.epc) return;
    if (['trial_recorded', 'trial_updated', 'reliability_changed'].includes(type)) trialsChanged();
    else if (type === 'learned_changed') learnedChanged();
    else if (type === 'tag_retagged') {
      const to = data.new_epc ?? data.to;
      replace(notice, h('p', { class: 'banner' }, 'This tag moved to a new EPC. ', to ? h('a', { href: `#/tags/${seg(to)}` }, 'Open it.') : null));
    } else if (['tag_changed', 'tag_archived'].includes(type)) tagChanged();
  });
  return () => {
    unsubscribe();
    for (const stop of stops) stop();
  };
}

export async function renderEdit(main, [epc]) {
  const { data: tag } = await request('GET', `/api/v1/tags/${seg(epc)}`);
  document.title = `Edit ${tag.properties?.name || tag.epc} · PPS-tag registry`;
  const body = h('div');
  replace(main,
    h('p', { class: 'crumbs' }, h('a', { href: `#/tags/${seg(tag.epc)}` }, `← ${tag.properties?.name || tag.epc}`)),
    h('h1', {}, `Edit “${tag.properties?.name || tag.epc}”`),
    h('p', { class: 'muted' }, `Editing revision ${tag.revision}. If someone else saves first, you will see what they changed before anything is overwritten.`),
    body);
  await mountEditor(body, {
    base: tag,
    entry: entryOf(tag),
    onSaved: (saved) => { location.hash = `#/tags/${seg(saved.epc)}`; },
    onCancel: () => { location.hash = `#/tags/${seg(tag.epc)}`; },
  });
}
