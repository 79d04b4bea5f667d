// JSON Pointers (RFC 6901): how the registry names a field in its validation errors, and how
// the form and the diff address the entry.

const escape = (key) => String(key).replaceAll('~', '~0').replaceAll('/', '~1');
const unescape = (part) => part.replaceAll('~1', '/').replaceAll('~0', '~');

/** "/a/b" from ["a", "b"]. */
export const join = (...keys) => keys.map((key) => `/${escape(key)}`).join('');

/** ["a", "b"] from "/a/b". */
export const split = (pointer) => (pointer ? pointer.split('/').slice(1).map(unescape) : []);

/** The value at a pointer, or undefined. */
export function getAt(value, pointer) {
  return split(pointer).reduce((at, key) => (at !== null && typeof at === 'object' ? at[key] : undefined), value);
}

/** Sets the value at a pointer, creating objects on the way; `undefined` deletes it. */
export function setAt(value, pointer, newValue) {
  const keys = split(pointer);
  const last = keys.pop();
  let at = value;
  for (const key of keys) {
    if (at[key] === null || typeof at[key] !== 'object') {
      if (newValue === undefined) return;
      at[key] = {};
    }
    at = at[key];
  }
  if (newValue === undefined) delete at[last];
  else at[last] = newValue;
}

/** The pointer one level up ("" for the whole document). */
export const parent = (pointer) => pointer.slice(0, pointer.lastIndexOf('/'));
