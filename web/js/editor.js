// Registering or editing a tag: the entry form, validation by the registry as you type, and a
// save that never overwrites silently: a new tag is created only if absent (If-None-Match: *),
// a change only applies to the revision it was made on (If-Match), and a conflict is shown.

import { ApiError, entryOf, etagOf, request, seg } from './api.js';
import { conflictPanel } from './conflict.js';
import { reapply } from './diff.js';
import { debounce, h, replace } from './dom.js';
import { EntryForm } from './entry-form.js';
import { loadSchemas } from './schema.js';

const VALIDATE_AFTER_MS = 350;

/**
 * Shows the editor in `container`. `base` is the tag as read (null for a new tag); `entry` the
 * starting entry. Calls `onSaved(tag)` after a successful save.
 */
export async function mountEditor(container, { base, entry, onSaved, onCancel }) {
  const schemas = await loadSchemas();
  let baseTag = base;
  // What the registry thinks of the entry as typed, and what became of the last save.
  const status = h('p', { class: 'status', role: 'status', 'aria-live': 'polite' });
  const saveStatus = h('p', { class: 'status bad', role: 'alert' });
  const conflictArea = h('div');
  let checks = 0;

  const validate = async () => {
    const mine = ++checks;
    status.textContent = 'Checking…';
    let errors = [];
    try {
      await request('POST', '/api/v1/validate/tag', { body: form.entry });
    } catch (error) {
      if (!(error instanceof ApiError) || error.status !== 422) {
        if (mine === checks) status.textContent = `Could not check: ${error.message}`;
        return;
      }
      errors = error.errors;
    }
    if (mine !== checks) return; // a newer check is under way
    form.showErrors(errors);
    const waiting = form.heldBack();
    if (errors.length === 0) status.textContent = 'No problems found.';
    else if (waiting.length === errors.length) status.textContent = `Still to fill in: ${[...new Set(waiting)].join('; ')}.`;
    else status.textContent = `${errors.length} ${errors.length === 1 ? 'problem' : 'problems'}: see the marked fields.`;
    status.classList.toggle('bad', errors.length > waiting.length);
  };
  const validateSoon = debounce(validate, VALIDATE_AFTER_MS);

  // A stored entry shows all its problems; a new one only those in fields already changed.
  const form = new EntryForm({ schemas, entry, epcEditable: !baseTag, revealAll: Boolean(baseTag), onChange: validateSoon });

  const save = async () => {
    saveButton.disabled = true;
    replace(saveStatus);
    form.reveal();
    const epc = String(form.entry.epc ?? '').trim();
    try {
      if (!epc) {
        await validate();
        return;
      }
      const headers = baseTag ? { 'If-Match': etagOf(baseTag.revision) } : { 'If-None-Match': '*' };
      const { data } = await request('PUT', `/api/v1/tags/${seg(epc)}`, { body: form.entry, headers });
      onSaved(data);
    } catch (error) {
      saveStatus.classList.add('bad');
      if (error.status === 422) {
        form.showErrors(error.errors);
        saveStatus.textContent = `Not saved: ${error.errors.length} ${error.errors.length === 1 ? 'problem' : 'problems'}, see the marked fields.`;
      } else if (error.status === 412 && baseTag) {
        await showConflict(epc);
      } else if (error.status === 412) {
        replace(saveStatus, 'Not saved: a tag with this EPC is registered already. ',
          h('a', { href: `#/tags/${seg(epc)}` }, 'Open it'), ' to edit it instead.');
      } else {
        saveStatus.textContent = `Not saved: ${error.message}`;
      }
    } finally {
      saveButton.disabled = false;
    }
  };

  const showConflict = async (epc) => {
    const theirsTag = (await request('GET', `/api/v1/tags/${seg(epc)}`)).data;
    const started = entryOf(baseTag);
    const mine = structuredClone(form.entry);
    const take = (next, message) => {
      baseTag = theirsTag;
      replace(conflictArea);
      form.setEntry(next);
      saveStatus.textContent = message;
      saveStatus.classList.remove('bad');
      saveButton.focus();
    };
    saveStatus.classList.add('bad');
    saveStatus.textContent = 'Not saved: someone else saved first; see above.';
    replace(conflictArea, conflictPanel({
      base: started,
      baseRevision: baseTag.revision,
      theirsTag,
      theirs: entryOf(theirsTag),
      mine,
      onReload: () => take(entryOf(theirsTag), `Loaded revision ${theirsTag.revision}; your changes were discarded.`),
      onReapply: () => take(reapply(started, entryOf(theirsTag), mine),
        `Your changes are applied on revision ${theirsTag.revision}; review them and save.`),
    }));
  };

  const saveButton = h('button', { type: 'button', class: 'primary', on: { click: save } }, baseTag ? 'Save changes' : 'Register tag');
  const cancel = h('button', { type: 'button', class: 'secondary', on: { click: onCancel } }, 'Cancel');
  replace(container, conflictArea, form.element, h('div', { class: 'save-bar' }, saveButton, cancel, status, saveStatus));
  validate();
  return form;
}
