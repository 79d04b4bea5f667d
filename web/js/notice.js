// A notice that survives a change of page: "Saved …" is said on the page a save leads to,
// in a status line that screen readers announce.

import { h, replace } from './dom.js';

const KEY = 'pps.notice';

/** Keeps `text` for the next page to show. */
export function leaveNotice(text) {
  try {
    sessionStorage.setItem(KEY, text);
  } catch {
    // Without storage the save still happened; the page simply does not say so.
  }
}

/**
 * A status line that shows the notice left for this page, if any. The text goes in only
 * once the line is in the document, so that screen readers announce it.
 */
export function noticeLine() {
  const line = h('p', { class: 'status saved', role: 'status', 'aria-live': 'polite' });
  let text = null;
  try {
    text = sessionStorage.getItem(KEY);
    sessionStorage.removeItem(KEY);
  } catch {
    text = null;
  }
  if (text) setTimeout(() => replace(line, text), 50);
  return line;
}
