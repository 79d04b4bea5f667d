// Registering a new tag: pick the tag a robot read but nobody registered (the inbox; one
// click), say what kind of device it is on, and give it a name and a room. Every other value
// starts from that kind of device's template; robot engineers may change them in the form's
// advanced section.

import { get, getAll, seg } from '../api.js';
import { h, replace } from '../dom.js';
import { mountEditor } from '../editor.js';
import { subscribe } from '../events.js';
import { ago } from '../format.js';
import { loadSchemas, titleOf } from '../schema.js';

/** A template as a new entry: the kind's values, with the name and the room left to fill in. */
function startFrom(template, epc) {
  const entry = { epc, ...structuredClone(template) };
  delete entry.properties.name;
  if (entry.properties.location) delete entry.properties.location.room;
  return entry;
}

export async function render(main, [epcFromUrl]) {
  document.title = 'Register a tag · PPS-tag registry';
  const [templates, schemas] = await Promise.all([get('/assets/templates.json'), loadSchemas()]);
  const kindTitle = (type) => titleOf(schemas.tag.$defs.properties.properties.type, type);
  const actionTitle = (action) => titleOf(schemas.tag.properties.actions, action);
  let chosenEpc = epcFromUrl ?? '';
  let form = null;
  const editorBox = h('div', { class: 'editor' });
  const inboxBox = h('div', { class: 'card' }, h('p', { class: 'muted' }, 'Loading…'));
  const picked = h('p', { class: 'status', role: 'status', 'aria-live': 'polite' });

  const useEpc = (epc, readBy) => {
    chosenEpc = epc;
    if (form) form.setEpc(epc);
    const which = readBy ? `The tag ${readBy} read` : 'That tag';
    picked.textContent = form ? `${which} is filled in below.` : `${which} is chosen; now pick what kind of device it is on.`;
  };

  const templateButtons = templates.map((template) => {
    const type = template.properties?.type ?? 'device';
    return h('button', {
      type: 'button', class: 'template', dataset: { template: type },
      on: {
        click: async (event) => {
          for (const button of main.querySelectorAll('button.template')) button.setAttribute('aria-pressed', String(button === event.currentTarget));
          form = await mountEditor(editorBox, {
            base: null,
            entry: startFrom(template, chosenEpc),
            onSaved: (tag) => { location.hash = `#/tags/${seg(tag.epc)}`; },
            onCancel: () => { location.hash = '#/tags'; },
          });
          const first = chosenEpc ? '[data-focus-key="/properties/name"]' : 'input[name="epc"]';
          editorBox.querySelector(first)?.focus();
        },
      },
    }, h('span', { class: 'template-type' }, kindTitle(type)),
    h('span', { class: 'muted' }, Object.keys(template.actions ?? {}).map(actionTitle).join(', ')));
  });

  const showInbox = async () => {
    try {
      const items = await getAll('/api/v1/inbox?limit=100', { maxPages: 1 });
      replace(inboxBox, items.length === 0
        ? h('p', { class: 'muted' }, 'No unregistered tags: robots have read only tags the registry knows.')
        : h('ul', { class: 'inbox' }, items.map((item) => {
          const robots = (item.robots ?? []).join(', ');
          return h('li', {},
            h('div', {},
              h('div', {}, `Read by ${robots || 'a robot'}, last ${ago(item.last_seen)}`, h('span', { class: 'muted' }, ` (${item.count} ×)`)),
              h('code', { class: 'epc muted' }, item.epc)),
            h('button', {
              type: 'button', class: 'secondary small', dataset: { epc: item.epc }, 'aria-label': `Use the tag ${item.epc}`,
              on: { click: () => useEpc(item.epc, robots) },
            }, 'Use this tag'));
        })));
    } catch (error) {
      replace(inboxBox, h('p', { class: 'status bad' }, `Could not load the inbox: ${error.message}`));
    }
  };

  replace(main,
    h('h1', {}, 'Register a tag'),
    h('p', { class: 'muted' }, 'Stick the tag on the device and let a robot read it. Then pick that tag, say what kind of device it is on, and give it a name and a room.'),
    h('section', { 'aria-labelledby': 'inbox-h' },
      h('h2', { id: 'inbox-h' }, 'Tags robots have read'),
      h('p', { class: 'help' }, 'Tags a robot read that nobody registered yet, newest first.'),
      inboxBox),
    h('section', { 'aria-labelledby': 'template-h' },
      h('h2', { id: 'template-h' }, 'What is it on?'),
      h('div', { class: 'templates' }, templateButtons),
      picked),
    editorBox);
  if (chosenEpc) picked.textContent = 'The tag is chosen; now pick what kind of device it is on.';
  await showInbox();
  return subscribe((type) => {
    if (type === 'inbox_changed') showInbox();
  });
}
