// Building the page with DOM APIs only. Data is always inserted as text nodes or attribute
// values, never parsed as HTML, so a tag named "<img src=x onerror=alert(1)>" shows as that
// text. Nothing in the UI may use innerHTML, insertAdjacentHTML or document.write.

const SVG_NS = 'http://www.w3.org/2000/svg';

/** Keys set as DOM properties (live state, or enumerated values such as spellcheck="false"). */
const PROPERTIES = new Set(['value', 'checked', 'disabled', 'hidden', 'readOnly', 'required', 'selected', 'spellcheck', 'noValidate']);

/**
 * Creates an element. `props` keys: `class`, `text`, `on` ({event: handler}), `dataset`, the
 * properties in PROPERTIES, and otherwise attributes (`true` sets an empty one, `false` none).
 * Children may be nodes, strings (as text), numbers, arrays, or null/false (skipped).
 */
export function h(tag, props = {}, ...children) {
  return build(document.createElement(tag), props, children);
}

/** Creates an SVG element with the same conventions as `h`. */
export function svg(tag, props = {}, ...children) {
  return build(document.createElementNS(SVG_NS, tag), props, children);
}

function build(element, props, children) {
  for (const [key, value] of Object.entries(props ?? {})) {
    if (value === undefined || value === null) continue;
    if (key === 'class') element.setAttribute('class', Array.isArray(value) ? value.filter(Boolean).join(' ') : value);
    else if (key === 'text') element.textContent = String(value);
    else if (key === 'on') for (const [event, handler] of Object.entries(value)) element.addEventListener(event, handler);
    else if (key === 'dataset') Object.assign(element.dataset, value);
    else if (PROPERTIES.has(key)) element[key] = value;
    else if (value !== false) element.setAttribute(key, value === true ? '' : String(value));
  }
  append(element, children);
  return element;
}

/** Appends children (nodes, text, arrays; null and false are skipped). */
export function append(parent, children) {
  for (const child of [children].flat(Infinity)) {
    if (child === null || child === undefined || child === false) continue;
    parent.append(child instanceof Node ? child : document.createTextNode(String(child)));
  }
  return parent;
}

/** Replaces all of a node's children. */
export function replace(parent, ...children) {
  parent.replaceChildren();
  return append(parent, children);
}

let idCounter = 0;

/** A document-unique id for tying labels, help and errors to fields. */
export function uid(prefix = 'f') {
  idCounter += 1;
  return `${prefix}-${idCounter}`;
}

/** A labelled form field: label, control, a help line and a slot for its error. */
export function field({ label, control, help, unit, className }) {
  const id = control.id || uid();
  control.id = id;
  const helpId = help ? `${id}-help` : null;
  const errorId = `${id}-error`;
  const describedBy = [helpId, errorId].filter(Boolean).join(' ');
  control.setAttribute('aria-describedby', describedBy);
  const error = h('p', { class: 'field-error', id: errorId, hidden: true });
  const wrapper = h('div', { class: ['field', className] },
    h('label', { for: id }, label),
    h('div', { class: 'control-row' }, control, unit ? h('span', { class: 'unit' }, unit) : null),
    help ? h('p', { class: 'help', id: helpId }, help) : null,
    error);
  return { wrapper, control, error };
}

/** Runs `fn` after `ms` of quiet: the latest call wins. */
export function debounce(fn, ms) {
  let timer = null;
  return (...args) => {
    clearTimeout(timer);
    timer = setTimeout(() => fn(...args), ms);
  };
}

/**
 * A table cell labelled for the card layout phones get: the label shows before the content
 * when the table's header row is hidden.
 */
export function cell(label, ...children) {
  return h('td', { dataset: { label } }, h('div', { class: 'cell' }, children));
}
