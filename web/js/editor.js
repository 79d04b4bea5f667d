// Registering or editing a tag: the entry form, validation by the registry as you type, and a
// save that never overwrites silently: a new tag is created only if absent (If-None-Match: *),
// a change only applies to the revision it was made on (If-Match), and a conflict is shown.
// One status line says how things stand: what the registry thinks of the entry as typed, or
// what became of the last save; it never says two things at once.

import { ApiError, entryOf, etagOf, request, seg } from './api.js';
import { conflictPanel } from './conflict.js';
import { reapply } from './diff.js';
import { debounce, h, replace } from './dom.js';
import { EntryForm } from './entry-form.js';
import { loadSchemas } from './schema.js';
import { leaveNotice } from './notice.js';

const VALIDATE_AFTER_MS = 350;

/**
 * Shows the editor in `container`. `base` is the tag as read (null for a new tag); `entry` the
 * starting entry. Calls `onSaved(tag)` after a successful save.
 */
export async function mountEditor(container, { base, entry, onSaved, onCancel }) {
  const schemas = await loadSchemas();
  let baseTag = base;
  const status = h('p', { class: 'status', role: 'status', 'aria-live': 'polite' });
  const say = (text, bad = false) => {
    replace(status, text);
    status.classList.toggle('bad', bad);
  };
  const conflictArea = h('div');
  let checks = 0;
  let nextStep = null;

  const validate = async () => {
    const mine = ++checks;
    if (form.jsonProblem) {
      say(`Not saved yet: ${form.jsonProblem}`, true);
      return;
    }
    say('Checking…');
    let errors = [];
    try {
      await request('POST', '/api/v1/validate/tag', { body: form.entry });
    } catch (error) {
      if (!(error instanceof ApiError) || error.status !== 422) {
        if (mine === checks) say(`Could not check: ${error.message}`, true);
        return;
      }
      errors = error.errors;
    }
    if (mine !== checks) return; // a newer check is under way
    form.showErrors(errors);
    const waiting = form.heldBack();
    if (errors.length === 0) say(nextStep ?? 'No problems found.');
    else if (waiting.length === errors.length) say(`Still to fill in: ${[...new Set(waiting)].join('; ')}.`);
    else say(`${errors.length} ${errors.length === 1 ? 'problem' : 'problems'}: see the marked fields.`, true);
  };
  const validateSoon = debounce(validate, VALIDATE_AFTER_MS);

  // A stored entry shows all its problems; a new one only those in fields already changed.
  const form = new EntryForm({ schemas, entry, epcEditable: !baseTag, revealAll: Boolean(baseTag), onChange: validateSoon });

  const save = async () => {
    if (form.jsonProblem) {
      say(`Not saved: ${form.jsonProblem}`, true);
      return;
    }
    saveButton.disabled = true;
    checks += 1; // a check still under way must not overwrite what the save says
    form.reveal();
    const epc = String(form.entry.epc ?? '').trim();
    try {
      if (!epc) {
        await validate();
        form.focusFirstError();
        return;
      }
      say('Saving…');
      const headers = baseTag ? { 'If-Match': etagOf(baseTag.revision) } : { 'If-None-Match': '*' };
      const { data } = await request('PUT', `/api/v1/tags/${seg(epc)}`, { body: form.entry, headers });
      leaveNotice(`Saved “${data.properties?.name ?? data.epc}”.`);
      onSaved(data);
    } catch (error) {
      if (error.status === 422) {
        form.showErrors(error.errors);
        say(`Not saved: ${error.errors.length} ${error.errors.length === 1 ? 'problem' : 'problems'}, see the marked fields.`, true);
        form.focusFirstError();
      } else if (error.status === 412 && baseTag) {
        await showConflict(epc);
      } else if (error.status === 412) {
        say(['Not saved: a tag with this EPC is registered already. ',
          h('a', { href: `#/tags/${seg(epc)}` }, 'Open it'), ' to edit it instead.'], true);
      } else {
        say(`Not saved: ${error.message}`, true);
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
      // Until the save, the status keeps saying what the caretaker should do next.
      nextStep = message;
      form.setEntry(next);
      say(message);
      saveButton.focus();
    };
    say('Not saved: someone else saved first; see above.', true);
    conflictArea.scrollIntoView({ block: 'start' });
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
  replace(container, conflictArea, form.element, h('div', { class: 'save-bar' }, saveButton, cancel, status));
  validate();
  return form;
}
