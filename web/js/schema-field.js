// One form control for one schema property: its kind, label, unit and help line all come from
// the schema. The value goes into the entry as typed; the registry judges it.

import { field, h } from './dom.js';
import { choicesOf, helpOf, kindOf, labelOf, unitOf } from './schema.js';

const NOT_SET = '';
const NUMBER = /^[-+]?(\d+\.?\d*|\.\d+)([eE][-+]?\d+)?$/;

/** The value a number field's text stands for: a number when it reads as one, else the text. */
function numberFrom(text) {
  const trimmed = text.trim().replace(',', '.');
  if (trimmed === '') return undefined;
  return NUMBER.test(trimmed) ? Number(trimmed) : text;
}

function optionList(values, current, required) {
  const options = required ? [] : [h('option', { value: NOT_SET }, '(not set)')];
  for (const [value, label] of values) options.push(h('option', { value }, label));
  const select = h('select', {}, options);
  select.value = current;
  return select;
}

/**
 * A labelled control for `prop` showing `value`; `onValue(newValue)` gets the new value
 * (`undefined` when cleared). Returns the field handle of `dom.field` or null for kinds the
 * form leaves to the JSON view.
 */
export function schemaField({ key, prop, value, required, focusKey, onValue }) {
  const kind = kindOf(prop);
  const label = labelOf(key, prop);
  const help = helpOf(prop);
  const unit = unitOf(prop);
  let control;
  switch (kind) {
    case 'enum': {
      const values = choicesOf(prop).map(([v, title]) => [JSON.stringify(v), title]);
      control = optionList(values, value === undefined ? NOT_SET : JSON.stringify(value), required);
      control.addEventListener('change', () => onValue(control.value === NOT_SET ? undefined : JSON.parse(control.value)));
      break;
    }
    case 'boolean': {
      control = optionList([['true', 'Yes'], ['false', 'No']], value === undefined ? NOT_SET : String(value), false);
      control.addEventListener('change', () => onValue(control.value === NOT_SET ? undefined : control.value === 'true'));
      break;
    }
    case 'number': {
      control = h('input', {
        type: 'text', inputMode: 'decimal', autocomplete: 'off',
        value: value === undefined ? '' : String(value),
        placeholder: prop.default !== undefined ? String(prop.default) : '',
      });
      control.addEventListener('input', () => onValue(numberFrom(control.value)));
      break;
    }
    case 'string': {
      control = h('input', { type: 'text', autocomplete: 'off', value: value ?? '' });
      control.addEventListener('input', () => onValue(control.value === '' && !required ? undefined : control.value));
      break;
    }
    case 'const': {
      control = h('input', { type: 'text', readOnly: true, value: String(prop.const) });
      break;
    }
    default:
      return null;
  }
  control.dataset.focusKey = focusKey;
  return field({ label, control, help, unit });
}
