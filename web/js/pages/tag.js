// One tag, followed. By default, what a caretaker knows: what it is, its name and room, what
// can be asked of it, how well that goes and what happened lately. Behind the advanced
// section, what robot engineers need: EPCs, behaviours and their parameters, per-robot
// values, success per kind of robot, learned values, the history of changes, retagging.
// Trials appear as robots record them (live feed). From here a caretaker edits, archives or
// restores the tag.

import { advancedSection } from '../advanced.js';
import { entryOf, etagOf, get, getAll, query, request, seg } from '../api.js';
import { successChart } from '../chart.js';
import { confirmDialog } from '../dialog.js';
import { debounce, h, replace, uid } from '../dom.js';
import { mountEditor } from '../editor.js';
import { subscribe } from '../events.js';
import { when } from '../format.js';
import { learnedInWords, learnedSizeInWords, sizeInCentimetres } from '../learned.js';
import { countedControl, countedInWords, noCountedTrials } from '../purpose.js';
import { noticeLine } from '../notice.js';
import { loadSchemas, titleOf, titlesFrom } from '../schema.js';
import { askControl } from './ask.js';
import { engineeringView } from './tag-engineering.js';
import { renderHistory } from './tag-history.js';
import { successRates } from './tag-rates.js';
import { robotView } from './tag-robots.js';
import { renderTrials } from './tag-trials.js';
import { renderLatestPicture } from '../picture.js';

/** The titles the schemas give a tag's values: its kind, its actions, a trial's outcome. */
function wordsFor(schemas, robots) {
  const names = new Map(robots.map((robot) => [robot.id, robot.name || robot.id]));
  return {
    ...titlesFrom(schemas),
    outcome: (outcome) => titleOf(schemas.trial.properties.outcome, outcome),
    robot: (id) => names.get(id) ?? id,
  };
}

/** Runs a section's loader, showing its failure in the section rather than failing the page. */
async function section(container, load) {
  try {
    await load();
  } catch (error) {
    replace(container, h('p', { class: 'status bad' }, `Could not load this part: ${error.message}`));
  }
}

function header(tag, { onArchive, onRestore, robots, stops, words }) {
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
      h('dt', {}, 'What it is'), h('dd', { class: 'tag-kind' }, p.type ? words.kind(p.type) : '—'),
      h('dt', {}, 'Room'), h('dd', { class: 'tag-room' }, p.location?.room ?? '—'),
      h('dt', {}, 'Last changed'), h('dd', {}, 'by ', h('span', {}, tag.updated_by ?? '—'), `, ${when(tag.updated_at)}`)),
    h('h2', {}, 'What you can ask for'),
    h('ul', { class: 'action-list' }, Object.keys(tag.actions ?? {}).map((action) => h('li', { dataset: { action } },
      h('strong', { class: 'action-title' }, words.action(action)),
      tag.archived ? null : askControl(tag, action, robots, stops)))));
}

/** The tag's size as the robots measured it; a size a caretaker registered is what they use. */
function learnedSizeView(stats, tag) {
  const seen = learnedSizeInWords(stats.learned_size);
  if (!seen) return null;
  const registered = tag.properties?.tag_size;
  const use = registered
    ? ` (robots use the size registered for it, ${sizeInCentimetres(registered)}).`
    : '. Robots use it until a size is registered for the tag.';
  return h('p', { class: 'learned-size' }, seen, use);
}

/** Success per action and kind of robot, and what was learned: for engineers. */
function statsView(stats, tag) {
  const groups = stats.groups ?? [];
  const counted = h('p', { class: 'counted' }, countedInWords(stats));
  if (groups.length === 0) return h('div', {}, counted, h('p', { class: 'muted' }, noCountedTrials(stats)));
  // The registry lists under each action only what that action's behaviour uses.
  const learned = groups.filter((g) => Object.keys(g.learned ?? {}).length > 0);
  const size = learnedSizeView(stats, tag);
  return h('div', {},
    counted,
    successChart(groups),
    h('p', { class: 'help' }, 'An action counts as reliable for a kind of robot after at least 20 attempts, at least 90 % of them successful (over its latest 50). A success is what the person confirmed, or else what the robot\'s own detector saw.'),
    h('h3', {}, 'Learned values'),
    size,
    learned.length === 0
      ? (size ? null : h('p', { class: 'muted' }, 'Nothing learned yet.'))
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
  const schemas = await loadSchemas();
  const saved = noticeLine();
  const notice = h('div', { 'aria-live': 'polite' });
  const head = h('div');
  const ratesBox = h('div', { class: 'card' }, h('p', { class: 'muted' }, 'Loading…'));
  const engineeringBox = h('div', { class: 'card' });
  const pictureBox = h('div', { class: 'card' }, h('p', { class: 'muted' }, 'Loading…'));
  const statsBox = h('div', { class: 'card' }, h('p', { class: 'muted' }, 'Loading…'));
  const trialsBox = h('div', { class: 'card', id: 'trials' }, h('p', { class: 'muted' }, 'Loading…'));
  const robotsBox = h('div', { class: 'card' }, h('p', { class: 'muted' }, 'Loading…'));
  const refreshRobots = robotView(robotsBox, tag.epc);
  const historyBox = h('div', { class: 'card' }, h('p', { class: 'muted' }, 'Loading…'));
  const retagBox = h('div');
  const robots = await getAll('/api/v1/robots?limit=500', { maxPages: 1 }).catch(() => []);
  const words = wordsFor(schemas, robots);
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
  const showHead = () => {
    replace(head, header(tag, { onArchive: archive, onRestore: restore, robots, stops, words }));
    replace(engineeringBox, engineeringView(tag, schemas));
  };
  // The latest stats, so that a size registered since says again which size robots use.
  let shownStats = null;
  const refreshTag = async () => {
    tag = await get(`/api/v1/tags/${seg(tag.epc)}`);
    showHead();
    if (shownStats) replace(statsBox, statsView(shownStats, tag));
    section(robotsBox, refreshRobots);
    section(historyBox, () => renderHistory(historyBox, tag.epc));
  };
  const refreshTrials = () => {
    // One read of the trials serves the list and the newest picture.
    const trials = renderTrials(trialsBox, tag.epc, words);
    section(trialsBox, () => trials);
    section(pictureBox, async () => renderLatestPicture(pictureBox, await trials));
    const include = query({ include: countedScope.include() });
    section(statsBox, async () => {
      const stats = await get(`/api/v1/tags/${seg(tag.epc)}/stats${include}`);
      const groups = stats.groups ?? [];
      replace(ratesBox, h('p', { class: 'counted' }, countedInWords(stats)),
        groups.length > 0 ? successRates(groups, words.action) : h('p', { class: 'muted' }, noCountedTrials(stats)));
      shownStats = stats;
      replace(statsBox, statsView(stats, tag));
    });
  };

  showHead();
  replace(main, saved, notice, head,
    h('section', { 'aria-labelledby': 'seen-h' }, h('h2', { id: 'seen-h' }, 'What the robot saw'), pictureBox),
    h('section', { 'aria-labelledby': 'rates-h' }, h('h2', { id: 'rates-h' }, 'How well it goes'), ratesBox, countedScope.element),
    h('section', { 'aria-labelledby': 'trials-h' }, h('h2', { id: 'trials-h' }, 'What happened lately'), trialsBox),
    advancedSection(
      h('section', { 'aria-labelledby': 'engineering-h' }, h('h3', { id: 'engineering-h', class: 'visually-hidden' }, 'The entry'), engineeringBox),
      h('section', { 'aria-labelledby': 'success-h' }, h('h3', { id: 'success-h' }, 'Success per action and kind of robot'), statsBox),
      h('section', { 'aria-labelledby': 'robots-h' }, h('h3', { id: 'robots-h' }, 'Per robot'),
        h('p', { class: 'help' }, 'What a robot gets when it reads this tag: values learned from its class\'s trials and per-robot overrides, and where each comes from.'), robotsBox),
      h('section', { 'aria-labelledby': 'history-h' }, h('h3', { id: 'history-h' }, 'History of changes'), historyBox),
      retagBox));
  refreshTrials();
  section(robotsBox, refreshRobots);
  section(historyBox, () => renderHistory(historyBox, tag.epc));
  const inbox = await getAll('/api/v1/inbox?limit=100', { maxPages: 1 }).catch(() => []);
  if (!tag.archived) replace(retagBox, retagForm(tag, inbox));

  const trialsChanged = debounce(refreshTrials, 150);
  const tagChanged = debounce(refreshTag, 150);
  const learnedChanged = debounce(() => {
    refreshTrials();
    section(robotsBox, refreshRobots);
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
    h('p', { class: 'crumbs' }, h('a', { href: `#/tags/${seg(tag.epc)}` }, `← ${tag.properties?.name || 'the tag'}`)),
    h('h1', {}, `Edit “${tag.properties?.name || 'this tag'}”`),
    h('p', { class: 'muted' }, 'If someone else saves first, you will see what they changed before anything is overwritten.'),
    body);
  await mountEditor(body, {
    base: tag,
    entry: entryOf(tag),
    onSaved: (saved) => { location.hash = `#/tags/${seg(saved.epc)}`; },
    onCancel: () => { location.hash = `#/tags/${seg(tag.epc)}`; },
  });
}
