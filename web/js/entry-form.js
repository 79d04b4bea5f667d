// The form for a tag entry. A caretaker sees what they know: the name, the room (and, for a
// new tag, its EPC). Everything else (the other properties, actions, behaviour parameters,
// the raw JSON) is laid out from the registry's schemas in the advanced section. The entry
// object is the one state; every control reads and writes it by JSON pointer, and errors
// from the registry are placed at the control their pointer names (or the nearest section
// that holds it), opening the advanced section when that is where they are.

import { advancedSection } from './advanced.js';
import { field, h, replace, uid } from './dom.js';
import { fieldPath } from './format.js';
import { getAt, join, parent, setAt, split } from './pointer.js';
import { appliesTo, choicesOf, deref, kindOf, labelOf, orderedKeys, propertiesOf, requiredOf } from './schema.js';
import { schemaField } from './schema-field.js';

/** A key not yet in `object`: "name", "name_2", … */
function freshKey(object, name) {
  let key = name;
  for (let n = 2; key in (object ?? {}); n += 1) key = `${name}_${n}`;
  return key;
}

/** The order fields are shown in: required ones, then by kind (text, choices, numbers, yes/no,
 * groups, JSON-only), each alphabetically as the registry lists them. */
const KIND_ORDER = ['string', 'enum', 'const', 'number', 'boolean', 'object', 'json'];
function displayOrder(props, required) {
  const rank = (key) => (required.includes(key) ? -1 : KIND_ORDER.indexOf(kindOf(props[key])));
  return Object.keys(props).sort((a, b) => rank(a) - rank(b));
}

/** The properties a caretaker fills in; the rest of `properties` is for engineers. */
const ESSENTIAL_PROPERTIES = ['name', 'location'];

/** `object` with one key renamed, keeping the order of keys. */
function renameKey(object, from, to) {
  return Object.fromEntries(Object.entries(object).map(([key, value]) => [key === from ? to : key, value]));
}

export class EntryForm {
  /**
   * @param {object} options
   * @param {object} options.schemas what `loadSchemas()` returns
   * @param {object} options.entry the entry to edit (kept and changed in place)
   * @param {boolean} options.epcEditable whether the EPC may be typed (a new tag)
   * @param {boolean} options.revealAll whether every error shows from the start; otherwise
   *   only errors in fields the caretaker changed show, until `reveal()` (a save attempt)
   * @param {() => void} options.onChange called after every change to the entry
   */
  constructor({ schemas, entry, epcEditable, revealAll, onChange }) {
    this.schemas = schemas;
    this.entry = entry;
    this.epcEditable = epcEditable;
    // A new tag's EPC is asked for beside the name, unless it came from the inbox already.
    this.epcAsked = epcEditable && !entry.epc;
    this.onChange = onChange;
    this.view = 'form';
    this.errors = [];
    this.touched = new Set();
    this.revealAll = revealAll;
    this.slots = new Map();
    this.general = h('ul', { class: 'problems', hidden: true, 'aria-live': 'polite' });
    this.body = h('div', { class: 'entry-form-body' });
    this.tabs = {
      form: h('button', { type: 'button', class: 'tab', on: { click: () => this.show('form') } }, 'Form'),
      json: h('button', { type: 'button', class: 'tab', on: { click: () => this.show('json') } }, 'JSON'),
    };
    this.jsonProblem = null;
    this.essentials = h('div', { class: 'essentials' });
    this.advanced = advancedSection(
      h('div', { class: 'tabs', role: 'group', 'aria-label': 'How to edit' }, this.tabs.form, this.tabs.json),
      this.body);
    this.element = h('div', { class: 'entry-form' }, this.general, this.essentials, this.advanced);
    this.render();
  }

  /** Replaces the whole entry (reload, reapply) and redraws. */
  setEntry(entry) {
    this.entry = entry;
    this.render();
    this.onChange();
  }

  /** Fills in the EPC (from the inbox). */
  setEpc(epc) {
    this.entry.epc = epc;
    this.epcAsked = false;
    this.render();
    this.onChange();
  }

  show(view) {
    this.view = view;
    // Leaving the JSON view drops text that did not parse; the form shows the last that did.
    this.jsonProblem = null;
    this.render();
    this.onChange();
  }

  changed(pointer, value) {
    setAt(this.entry, pointer, value);
    if (value === undefined) this.dropEmptyGroups(pointer);
    this.touched.add(pointer);
    this.onChange();
  }

  /**
   * A group of properties left empty once its last field is cleared (a tag's size) goes too:
   * kept, it would ask for the fields it requires, though the caretaker meant to leave it out.
   */
  dropEmptyGroups(pointer) {
    for (let at = parent(pointer); split(at).length >= 2; at = parent(at)) {
      const group = getAt(this.entry, at);
      if (group === null || typeof group !== 'object' || Object.keys(group).length) return;
      setAt(this.entry, at, undefined);
    }
  }

  /** Shows every error from now on, also in fields not changed yet (after a save attempt). */
  reveal() {
    this.revealAll = true;
    this.showErrors(this.errors);
  }

  /** Whether an error concerns something the caretaker changed, or is to be shown anyway. */
  shown(error) {
    if (this.revealAll || this.view === 'json') return true;
    const at = error.pointer ?? '';
    return [...this.touched].some((t) => at === t || at.startsWith(`${t}/`) || t.startsWith(`${at}/`));
  }

  /** The errors held back until a save attempt, as the labels of their fields. */
  heldBack() {
    return this.errors.filter((error) => !this.shown(error)).map((error) => this.labelAt(error.pointer ?? ''));
  }

  /** The label a field shows, for naming it in the status line; its path when it has none. */
  labelAt(pointer) {
    const wrapper = this.slots.get(pointer)?.wrapper;
    const label = wrapper?.querySelector(':scope > label, :scope > .label, :scope > legend')?.textContent;
    return label ? label.charAt(0).toLowerCase() + label.slice(1) : fieldPath(pointer);
  }

  /** Changes the structure (keys added, removed or renamed): redraw, keeping the focus. */
  restructure(section, mutate) {
    this.touched.add(section);
    mutate();
    const focused = document.activeElement?.dataset?.focusKey;
    this.render();
    if (focused) this.body.querySelector(`[data-focus-key="${CSS.escape(focused)}"]`)?.focus();
    this.onChange();
  }

  render() {
    this.slots = new Map();
    for (const [name, tab] of Object.entries(this.tabs)) tab.setAttribute('aria-pressed', String(this.view === name));
    if (this.view === 'json') {
      replace(this.essentials, h('p', { class: 'help' }, 'The JSON below holds every field, the name and room included.'));
      replace(this.body, this.jsonView());
    } else {
      replace(this.essentials, this.essentialsSection());
      replace(this.body, this.epcAsked ? null : this.epcSection(), this.propertiesSection(), this.actionsSection(), this.behaviorsSection(), this.linksSection());
    }
    this.showErrors(this.errors);
  }

  // Where errors go: a field's error line, or a section's.
  slot(pointer, handle) {
    this.slots.set(pointer, handle);
    return handle;
  }

  section(pointer, title, help, ...content) {
    const error = h('p', { class: 'field-error', hidden: true });
    const wrapper = h('fieldset', { class: 'section', dataset: { pointer } },
      h('legend', {}, title), help ? h('p', { class: 'help' }, help) : null, error, content);
    this.slot(pointer, { wrapper, error });
    return wrapper;
  }

  /** What a caretaker knows: the name and the room; for a new tag also its EPC. */
  essentialsSection() {
    const tag = this.schemas.tag;
    const props = propertiesOf(tag, deref(tag, tag.properties.properties));
    const room = propertiesOf(tag, props.location).room;
    return h('div', { class: 'grid essential-fields' },
      this.epcAsked ? this.epcSection() : null,
      this.propertyField(tag, '/properties/name', 'name', props.name, true),
      this.propertyField(tag, '/properties/location/room', 'room', room, false));
  }

  epcSection() {
    const epcSchema = deref(this.schemas.tag, this.schemas.tag.properties.epc);
    const control = h('input', {
      type: 'text', name: 'epc', autocomplete: 'off', spellcheck: false, value: this.entry.epc ?? '',
      readOnly: !this.epcEditable, dataset: { focusKey: '/epc' },
    });
    control.addEventListener('input', () => this.changed('/epc', control.value.trim()));
    const epcField = field({ label: epcSchema.title ?? 'EPC', control, help: this.epcAsked ? 'Filled in when you pick a tag a robot has read; otherwise type the number printed on the tag.' : epcSchema.description });
    this.slot('/epc', epcField);
    return h('div', { class: 'epc-field' }, epcField.wrapper);
  }

  propertiesSection() {
    const tag = this.schemas.tag;
    const node = deref(tag, tag.properties.properties);
    const props = propertiesOf(tag, node);
    const required = requiredOf(tag, node);
    const values = this.entry.properties ?? {};
    // Only what applies to this kind of device, unless it is set anyway.
    const keys = displayOrder(props, required).filter((key) => !ESSENTIAL_PROPERTIES.includes(key)
      && (appliesTo(props[key], values.type) || values[key] !== undefined));
    const extra = Object.keys(values).filter((key) => !(key in props));
    return this.section('/properties', node.title ?? 'Properties', node.description,
      h('div', { class: 'grid' }, keys.map((key) => this.propertyField(tag, join('properties', key), key, props[key], required.includes(key)))),
      extra.length ? h('p', { class: 'help' }, `Also kept as they are (edit in the JSON view): ${extra.join(', ')}.`) : null);
  }

  /** One property: a control, a nested group for an object, or a note for the JSON view. */
  propertyField(doc, pointer, key, prop, required) {
    if (prop.type === 'object' && prop.properties) {
      const inner = propertiesOf(doc, prop);
      return this.section(pointer, labelOf(key, prop), prop.description,
        h('div', { class: 'grid' }, orderedKeys(prop, Object.keys(inner)).map((k) => this.propertyField(doc, `${pointer}${join(k)}`, k, inner[k], (prop.required ?? []).includes(k)))));
    }
    const handle = schemaField({
      key, prop, required, focusKey: pointer, value: getAt(this.entry, pointer),
      onValue: (value) => this.changed(pointer, value),
    });
    if (handle) return this.slot(pointer, handle).wrapper;
    return this.jsonNote(pointer, key, prop);
  }

  /** A setting the form does not edit (per-robot overrides, colour thresholds, links). */
  jsonNote(pointer, key, prop) {
    const value = getAt(this.entry, pointer);
    const count = value === undefined ? 0 : typeof value === 'object' ? Object.keys(value).length : 1;
    const error = h('p', { class: 'field-error', hidden: true });
    const wrapper = h('div', { class: 'field json-note' },
      h('span', { class: 'label' }, labelOf(key, prop)),
      h('p', { class: 'help' }, `${count ? `${count} set` : 'None set'}; edit in the JSON view. ${prop.description ?? ''}`),
      error);
    this.slot(pointer, { wrapper, error });
    return wrapper;
  }

  actionsSection() {
    const tag = this.schemas.tag;
    const actions = this.entry.actions ?? {};
    const behaviorKeys = Object.keys(this.entry.behaviors ?? {});
    const rows = Object.entries(actions).map(([name, target]) => this.actionRow(name, target, behaviorKeys));
    const add = h('button', {
      type: 'button', class: 'secondary', dataset: { focusKey: 'add-action' },
      on: { click: () => this.restructure('/actions', () => { this.entry.actions = { ...actions, [freshKey(actions, 'action')]: behaviorKeys[0] ?? '' }; }) },
    }, 'Add action');
    return this.section('/actions', tag.properties.actions.title ?? 'Actions', tag.properties.actions.description,
      h('div', { class: 'rows' }, rows), add);
  }

  actionRow(name, target, behaviorKeys) {
    const pointer = join('actions', name);
    const nameInput = h('input', { type: 'text', value: name, autocomplete: 'off', dataset: { focusKey: `${pointer}#name` } });
    nameInput.addEventListener('change', () => {
      const to = nameInput.value.trim();
      if (to && to !== name && !(to in this.entry.actions)) this.restructure('/actions', () => { this.entry.actions = renameKey(this.entry.actions, name, to); });
    });
    const choices = behaviorKeys.includes(target) ? behaviorKeys : [target, ...behaviorKeys];
    const select = h('select', { dataset: { focusKey: pointer } }, choices.map((key) => h('option', { value: key }, key)));
    select.value = target;
    select.addEventListener('change', () => this.changed(pointer, select.value));
    const nameField = field({ label: 'Action', control: nameInput });
    const targetField = field({ label: 'Runs behaviour', control: select });
    this.slot(pointer, targetField);
    const remove = h('button', {
      type: 'button', class: 'link danger', 'aria-label': `Remove action ${name}`,
      on: { click: () => this.restructure('/actions', () => { delete this.entry.actions[name]; }) },
    }, 'Remove');
    return h('div', { class: 'row action-row' }, nameField.wrapper, targetField.wrapper, remove);
  }

  behaviorsSection() {
    const tag = this.schemas.tag;
    const behaviors = this.entry.behaviors ?? {};
    const add = h('button', {
      type: 'button', class: 'secondary', dataset: { focusKey: 'add-behavior' },
      on: {
        click: () => this.restructure('/behaviors', () => {
          this.entry.behaviors = { ...behaviors, [freshKey(behaviors, 'behavior')]: { behavior: this.schemas.behaviorNames[0] } };
        }),
      },
    }, 'Add behaviour');
    return this.section('/behaviors', tag.properties.behaviors.title ?? 'Behaviours', tag.properties.behaviors.description,
      Object.entries(behaviors).map(([key, spec]) => this.behaviorGroup(key, spec)), add);
  }

  behaviorGroup(key, spec) {
    const pointer = join('behaviors', key);
    const kindNames = this.schemas.behaviorNames;
    const doc = this.schemas.behaviors[spec?.behavior];
    const keyInput = h('input', { type: 'text', value: key, autocomplete: 'off', dataset: { focusKey: `${pointer}#key` } });
    keyInput.addEventListener('change', () => {
      const to = keyInput.value.trim();
      if (!to || to === key || to in this.entry.behaviors) return;
      this.restructure('/behaviors', () => {
        this.entry.behaviors = renameKey(this.entry.behaviors, key, to);
        for (const [action, target] of Object.entries(this.entry.actions ?? {})) if (target === key) this.entry.actions[action] = to;
      });
    });
    const titles = new Map(choicesOf(this.schemas.tag.$defs?.behavior_name ?? {}));
    const kind = h('select', { dataset: { focusKey: `${pointer}/behavior` } }, kindNames.map((name) => h('option', { value: name }, titles.get(name) ?? name)));
    kind.value = spec?.behavior ?? '';
    kind.addEventListener('change', () => this.restructure(pointer, () => {
      // Keep only the parameters the new behaviour's schema has.
      const known = propertiesOf(this.schemas.behaviors[kind.value], this.schemas.behaviors[kind.value]);
      const kept = Object.fromEntries(Object.entries(spec).filter(([k]) => k in known));
      this.entry.behaviors[key] = { ...kept, behavior: kind.value };
    }));
    const kindField = field({ label: 'Robot behaviour', control: kind, help: this.schemas.tag.$defs?.behavior_name?.description });
    if (doc?.description) kindField.wrapper.append(h('details', { class: 'help' }, h('summary', {}, 'How this behaviour works'), doc.description));
    this.slot(`${pointer}/behavior`, kindField);
    const params = doc ? Object.fromEntries(Object.entries(propertiesOf(doc, doc)).filter(([name]) => name !== 'behavior')) : {};
    const required = doc?.required ?? [];
    const remove = h('button', {
      type: 'button', class: 'link danger', 'aria-label': `Remove behaviour ${key}`,
      on: { click: () => this.restructure('/behaviors', () => { delete this.entry.behaviors[key]; }) },
    }, 'Remove behaviour');
    return this.section(pointer, `Behaviour “${key}”`, null,
      h('div', { class: 'grid' },
        field({ label: 'Name (what actions refer to)', control: keyInput }).wrapper,
        kindField.wrapper,
        displayOrder(params, required).map((name) => this.propertyField(doc, `${pointer}${join(name)}`, name, params[name], required.includes(name)))),
      remove);
  }

  linksSection() {
    const tag = this.schemas.tag;
    const prop = deref(tag, tag.properties.links);
    return h('div', { class: 'grid' }, this.jsonNote('/links', 'links', prop));
  }

  jsonView() {
    const id = uid('json');
    const text = h('textarea', { id, class: 'json', rows: 24, spellcheck: false, value: JSON.stringify(this.entry, null, 2), dataset: { focusKey: 'json' } });
    // The parse error sits above the box, where it stays in view while typing.
    const problem = h('p', { class: 'field-error', id: `${id}-problem`, hidden: true });
    text.setAttribute('aria-describedby', problem.id);
    text.addEventListener('input', () => {
      try {
        const parsed = JSON.parse(text.value);
        problem.hidden = true;
        text.removeAttribute('aria-invalid');
        this.jsonProblem = null;
        this.entry = parsed;
      } catch (error) {
        problem.hidden = false;
        this.jsonProblem = `the JSON does not parse: ${error.message}`;
        problem.textContent = `Not valid JSON yet: ${error.message}`;
        text.setAttribute('aria-invalid', 'true');
      }
      this.onChange();
    });
    return h('div', { class: 'field' }, h('label', { for: id }, 'The entry as JSON'), problem, text);
  }

  /** Places the registry's errors: at their field, else the nearest section, else on top. */
  showErrors(errors) {
    this.errors = errors;
    const byHandle = new Map();
    const unplaced = [];
    for (const error of errors.filter((e) => this.shown(e))) {
      let at = error.pointer ?? '';
      while (at && !this.slots.has(at)) at = parent(at);
      const handle = this.view === 'form' ? this.slots.get(at) : undefined;
      if (!handle) {
        unplaced.push(error);
        continue;
      }
      const text = at === error.pointer ? error.message : `${fieldPath(error.pointer.slice(at.length))}: ${error.message}`;
      byHandle.set(handle, [...(byHandle.get(handle) ?? []), text]);
    }
    for (const handle of new Set(this.slots.values())) {
      const messages = byHandle.get(handle) ?? [];
      handle.error.hidden = messages.length === 0;
      replace(handle.error, messages.map((message) => h('span', {}, message)));
      handle.wrapper.classList.toggle('has-error', messages.length > 0);
      if (handle.control) {
        if (messages.length) handle.control.setAttribute('aria-invalid', 'true');
        else handle.control.removeAttribute('aria-invalid');
      }
    }
    this.general.hidden = unplaced.length === 0;
    replace(this.general, unplaced.map((error) => h('li', {}, `${fieldPath(error.pointer)}: ${error.message}`)));
    const inside = [...byHandle.keys()].filter((handle) => this.advanced.contains(handle.wrapper)).length;
    this.advanced.note(inside ? `${inside} ${inside === 1 ? 'field needs' : 'fields need'} attention` : '');
  }

  /** Brings the first error into view and puts the focus on it, opening what hides it. */
  focusFirstError() {
    const target = !this.general.hidden ? this.general
      : this.element.querySelector('.field-error:not([hidden]), .has-error');
    if (!target) return false;
    if (this.advanced.contains(target)) this.advanced.reveal();
    const holder = target.closest('.field, fieldset') ?? target;
    const control = holder.querySelector('input:not([readonly]), select, textarea') ?? holder;
    if (!control.hasAttribute('tabindex') && control === holder) control.setAttribute('tabindex', '-1');
    control.focus({ preventScroll: true });
    holder.scrollIntoView({ block: 'center' });
    return true;
  }
}
