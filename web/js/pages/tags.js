// The landing page: every tag with what a caretaker wants at a glance (name, a picture of what
// the robot saw, what it is, room, the last trial, the success rate, whether it is reliable),
// search, a filter by kind, and the archived tags on request with a way to restore them. The
// EPC is an engineer's word: it is on the tag's page, in its advanced section.

import { ApiError, etagOf, entryOf, get, query, request, seg } from '../api.js';
import { cell, debounce, h, replace, uid } from '../dom.js';
import { subscribe } from '../events.js';
import { ago, percent } from '../format.js';
import { tagThumbnail } from '../picture.js';
import { loadSchemas, titlesFrom } from '../schema.js';

const PAGE_SIZE = 100;
/** How many stats requests run at once, so a long list does not flood the registry. */
const STATS_IN_FLIGHT = 4;

/** One line summing up a tag's stats groups. */
export function summarise(groups) {
  const attempts = groups.reduce((n, g) => n + (g.attempts ?? 0), 0);
  const last = groups.map((g) => g.last_attempt).filter(Boolean).sort().at(-1) ?? null;
  const rated = groups.filter((g) => typeof g.success_rate === 'number' && g.attempts > 0);
  const rate = rated.length
    ? rated.reduce((sum, g) => sum + g.success_rate * g.attempts, 0) / rated.reduce((n, g) => n + g.attempts, 0)
    : null;
  const reliable = groups.filter((g) => g.reliable).length;
  const reliability = attempts === 0 ? 'no trials yet'
    : reliable === groups.length ? 'reliable' : reliable > 0 ? 'partly reliable' : 'not yet reliable';
  return { attempts, last, rate, reliability };
}

export async function render(main) {
  document.title = 'Tags · PPS-tag registry';
  const templates = await get('/assets/templates.json').catch(() => []);
  const { kind } = titlesFrom(await loadSchemas());
  const knownTypes = new Set(templates.map((t) => t.properties?.type).filter(Boolean));

  const searchId = uid('search');
  const typeId = uid('type');
  const archivedId = uid('archived');
  const search = h('input', { id: searchId, type: 'search', placeholder: 'Name contains…', autocomplete: 'off' });
  const typeSelect = h('select', { id: typeId });
  const archived = h('input', { id: archivedId, type: 'checkbox' });
  const status = h('p', { class: 'status', role: 'status', 'aria-live': 'polite' });
  const tbody = h('tbody');
  const more = h('button', { type: 'button', class: 'secondary', hidden: true }, 'Show more');
  let cursor = null;
  let generation = 0;
  const rows = new Map();

  const fillTypes = () => {
    const chosen = typeSelect.value;
    replace(typeSelect, h('option', { value: '' }, 'All types'),
      [...knownTypes].sort().map((type) => h('option', { value: type }, kind(type))));
    typeSelect.value = chosen;
  };
  fillTypes();

  const statsCells = (epc, cells) => async () => {
    try {
      const { groups = [] } = await get(`/api/v1/tags/${seg(epc)}/stats`);
      const s = summarise(groups);
      replace(cells.last, s.last ? ago(s.last) : 'never');
      replace(cells.rate, s.attempts ? `${percent(s.rate)} of ${s.attempts}` : '—');
      replace(cells.reliability, h('span', { class: ['badge', s.reliability === 'reliable' ? 'good' : s.attempts ? 'warn' : null] }, s.reliability));
    } catch {
      for (const slot of Object.values(cells)) replace(slot, '—');
    }
  };

  const restore = async (tag, button) => {
    button.disabled = true;
    try {
      const { data: current } = await request('GET', `/api/v1/tags/${seg(tag.epc)}`);
      await request('PUT', `/api/v1/tags/${seg(tag.epc)}`, { body: entryOf(current), headers: { 'If-Match': etagOf(current.revision) } });
      await load();
      status.textContent = `Restored “${tag.properties?.name ?? tag.epc}”: robots get it again.`;
    } catch (error) {
      status.textContent = `Not restored: ${error.message}`;
      button.disabled = false;
    }
  };

  const row = (tag) => {
    const cells = { last: h('div', {}, '…'), rate: h('div', {}, '…'), reliability: h('div', {}, '…') };
    const name = tag.properties?.name || '(no name)';
    const restoreButton = tag.archived ? h('button', { type: 'button', class: 'secondary small' }, 'Restore') : null;
    restoreButton?.addEventListener('click', () => restore(tag, restoreButton));
    const tr = h('tr', { dataset: { epc: tag.epc } },
      h('th', { scope: 'row', dataset: { label: 'Name' } }, h('a', { href: `#/tags/${seg(tag.epc)}`, class: 'tag-name' }, name),
        tag.archived ? h('span', { class: 'badge' }, 'archived') : null, tagThumbnail(tag.epc, name)),
      cell('What it is', tag.properties?.type ? kind(tag.properties.type) : '—'),
      cell('Room', tag.properties?.location?.room ?? '—'),
      cell('Last trial', cells.last), cell('Success', cells.rate), cell('Reliability', cells.reliability),
      h('td', { class: 'row-actions' }, restoreButton));
    rows.set(tag.epc, statsCells(tag.epc, cells));
    return tr;
  };

  /** Runs the stats look-ups a few at a time. */
  const fetchStats = async (jobs, mine) => {
    const queue = [...jobs];
    const worker = async () => {
      while (queue.length && mine === generation) await queue.shift()();
    };
    await Promise.all(Array.from({ length: STATS_IN_FLIGHT }, worker));
  };

  const load = async ({ append = false } = {}) => {
    const mine = ++generation;
    status.textContent = 'Loading…';
    const path = `/api/v1/tags${query({ q: search.value.trim(), type: typeSelect.value, archived: archived.checked ? 'true' : '', limit: PAGE_SIZE, cursor: append ? cursor : '' })}`;
    let page;
    try {
      page = await get(path);
    } catch (error) {
      if (mine === generation) status.textContent = error instanceof ApiError ? error.message : `Could not load the tags: ${error.message}`;
      return;
    }
    if (mine !== generation) return;
    if (!append) {
      replace(tbody);
      rows.clear();
    }
    const trs = page.items.map(row);
    tbody.append(...trs);
    for (const tag of page.items) if (tag.properties?.type) knownTypes.add(tag.properties.type);
    fillTypes();
    cursor = page.next_cursor;
    more.hidden = !cursor;
    const shown = tbody.rows.length;
    status.textContent = shown === 0
      ? (archived.checked ? 'No archived tags match.' : 'No tags match.')
      : `${shown} ${archived.checked ? 'archived ' : ''}${shown === 1 ? 'tag' : 'tags'}${cursor ? ' so far' : ''}.`;
    fetchStats(page.items.map((tag) => rows.get(tag.epc)), mine);
  };

  search.addEventListener('input', debounce(() => load(), 250));
  typeSelect.addEventListener('change', () => load());
  archived.addEventListener('change', () => load());
  more.addEventListener('click', () => load({ append: true }));

  replace(main,
    h('div', { class: 'page-head' },
      h('h1', {}, 'Tags'),
      h('a', { class: 'button primary', href: '#/register' }, 'Register a tag')),
    h('form', { class: 'filters', role: 'search', on: { submit: (e) => { e.preventDefault(); load(); } } },
      h('div', { class: 'field' }, h('label', { for: searchId }, 'Search'), search),
      h('div', { class: 'field' }, h('label', { for: typeId }, 'What it is'), typeSelect),
      h('div', { class: 'field checkbox' }, archived, h('label', { for: archivedId }, 'Show archived tags'))),
    status,
    h('table', { class: 'tags responsive' },
      h('caption', { class: 'visually-hidden' }, 'Registered tags'),
      h('thead', {}, h('tr', {}, ['Name', 'What it is', 'Room', 'Last trial', 'Success', 'Reliability', ''].map((label) => h('th', { scope: 'col' }, label)))),
      tbody),
    more);
  await load();

  const reload = debounce(() => load(), 300);
  return subscribe((type, data) => {
    if (['tag_changed', 'tag_archived', 'tag_retagged'].includes(type)) reload();
    else if (['trial_recorded', 'trial_updated', 'reliability_changed'].includes(type) && rows.has(data.epc)) rows.get(data.epc)();
  });
}
