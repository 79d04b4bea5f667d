// The "Advanced (for robot engineers)" section: what only robot engineers need (behaviour
// parameters, overrides, colour settings, EPCs, the JSON) stays out of a caretaker's way. It
// is closed until someone opens it, and each user's choice is remembered in this browser.

import { h } from './dom.js';
import { recalled, remember } from './preference.js';

const TITLE = 'Advanced (for robot engineers)';
const PREFERENCE = 'advanced-open';

/**
 * A closed-by-default section holding `children`. Returns the `<details>` element with
 * `reveal()`: opens it for the moment (to show an error inside) without changing what is
 * remembered, and `note(text)`: a short remark shown beside the title (e.g. "2 problems").
 */
export function advancedSection(...children) {
  const remark = h('span', { class: 'advanced-note' });
  const details = h('details', { class: 'advanced', open: recalled(PREFERENCE) === 'open' },
    h('summary', {}, TITLE, remark), children);
  let revealing = false;
  details.addEventListener('toggle', () => {
    if (revealing) revealing = false;
    else remember(PREFERENCE, details.open ? 'open' : 'closed');
  });
  details.reveal = () => {
    if (details.open) return;
    revealing = true;
    details.open = true;
  };
  details.note = (text) => {
    remark.textContent = text ? ` · ${text}` : '';
  };
  return details;
}
