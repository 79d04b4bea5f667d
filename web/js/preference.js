// Choices a person makes about what a page shows (an open section, a ticked box), remembered
// per user in this browser. Storage may be switched off: then nothing is remembered, and the
// page still works with its defaults.

import * as session from './session.js';

const key = (name) => `pps.${name}.${session.user()?.name ?? ''}`;

/** The value this user last chose for `name`, or null when nothing is remembered. */
export function recalled(name) {
  try {
    return localStorage.getItem(key(name));
  } catch {
    return null;
  }
}

/** Remembers `value` as this user's choice for `name`. */
export function remember(name, value) {
  try {
    localStorage.setItem(key(name), value);
  } catch {
    // Not remembered; the choice still holds on this page.
  }
}
