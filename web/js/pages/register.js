// Registering a new tag: start from one of the paper's five devices, take the EPC from the
// inbox of tags robots read but nobody registered (one click), then fill in the form.

import { get, getAll, seg } from '../api.js';
import { h, replace } from '../dom.js';
import { mountEditor } from '../editor.js';
import { subscribe } from '../events.js';
import { ago } from '../format.js';

export async function render(main, [epcFromUrl]) {
  document.title = 'Register a tag · PPS-tag registry';
  const templates = await get('/assets/templates.json');
  let chosenEpc = epcFromUrl ?? '';
  let form = null;
  const editorBox = h('div', { class: 'editor' });
  const inboxBox = h('div', { class: 'card' }, h('p', { class: 'muted' }, 'Loading…'));
  const picked = h('p', { class: 'status', role: 'status', 'aria-live': 'polite' });

  const useEpc = (epc) => {
    chosenEpc = epc;
    if (form) form.setEpc(epc);
    picked.textContent = form ? `EPC ${epc} filled in below.` : `EPC ${epc} chosen; now pick what kind of device it is on.`;
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
            entry: { epc: chosenEpc, ...structuredClone(template) },
            onSaved: (tag) => { location.hash = `#/tags/${seg(tag.epc)}`; },
            onCancel: () => { location.hash = '#/tags'; },
          });
          editorBox.querySelector('input[name="epc"]')?.focus();
        },
      },
    }, h('span', { class: 'template-type' }, type),
    h('span', { class: 'muted' }, Object.keys(template.actions ?? {}).join(', ')));
  });

  const showInbox = async () => {
    try {
      const items = await getAll('/api/v1/inbox?limit=100', { maxPages: 1 });
      replace(inboxBox, items.length === 0
        ? h('p', { class: 'muted' }, 'No unregistered tags: robots have read only tags the registry knows.')
        : h('ul', { class: 'inbox' }, items.map((item) => h('li', {},
          h('div', {}, h('code', { class: 'epc' }, item.epc), item.epc_uri ? h('div', { class: 'uri' }, item.epc_uri) : null,
            h('div', { class: 'muted' }, `read ${item.count} × by ${(item.robots ?? []).join(', ')}, last ${ago(item.last_seen)}`)),
          h('button', { type: 'button', class: 'secondary small', dataset: { epc: item.epc }, 'aria-label': `Use EPC ${item.epc}`, on: { click: () => useEpc(item.epc) } }, 'Use this EPC')))));
    } catch (error) {
      replace(inboxBox, h('p', { class: 'status bad' }, `Could not load the inbox: ${error.message}`));
    }
  };

  replace(main,
    h('h1', {}, 'Register a tag'),
    h('p', { class: 'muted' }, 'Stick the tag on the device, then start from the kind of device and fill in the rest. The registry checks every field as you type.'),
    h('section', { 'aria-labelledby': 'inbox-h' },
      h('h2', { id: 'inbox-h' }, 'Tags robots have read'),
      h('p', { class: 'help' }, 'EPCs a robot read that nobody registered yet. Pick yours to fill in its EPC.'),
      inboxBox),
    h('section', { 'aria-labelledby': 'template-h' },
      h('h2', { id: 'template-h' }, 'What is it on?'),
      h('div', { class: 'templates' }, templateButtons),
      picked),
    editorBox);
  if (chosenEpc) picked.textContent = `EPC ${chosenEpc} chosen; now pick what kind of device it is on.`;
  await showInbox();
  return subscribe((type) => {
    if (type === 'inbox_changed') showInbox();
  });
}
