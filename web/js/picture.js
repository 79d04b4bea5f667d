// What the robot saw: the picture a robot sends with a trial, its camera's view around the tag
// with what perception made of it drawn in (the paper's Fig. 5) and a legend. Pictures come
// from the registry itself (same origin, with the session cookie); each has an alt text that
// says in words what it shows, since the picture alone tells a screen reader nothing.

import { seg } from './api.js';
import { h } from './dom.js';
import { when } from './format.js';

/** The alt text of a trial's picture. */
export function describe(trial) {
  // The action's key is an internal name; the time and the robot say which trial it was.
  return `What ${trial.robot} saw, ${when(trial.started_at ?? trial.finished_at)}`;
}

/** A trial's picture, linked to the full size; a small thumbnail when asked; null without one. */
export function trialPicture(trial, { thumbnail = false } = {}) {
  if (!trial?.picture) return null;
  const image = h('img', { src: trial.picture, alt: describe(trial), loading: 'lazy', class: ['picture', thumbnail && 'thumbnail'] });
  return h('a', { href: trial.picture, target: '_blank', rel: 'noopener', class: 'picture-link' }, image);
}

/** Fills `container` with the newest picture among a tag's `trials` (in the order the
 * registry received them; a picture follows its trial) and what it shows. */
export function renderLatestPicture(container, trials) {
  const trial = trials.filter((t) => t.picture).at(-1);
  if (!trial) {
    container.replaceChildren(h('p', { class: 'muted' }, 'No robot has sent a picture of this tag yet.'));
    return;
  }
  container.replaceChildren(h('figure', { class: 'robot-view' }, trialPicture(trial),
    h('figcaption', {}, `${describe(trial)}. Cyan: where it looked; red: the tag; dark green: the surface behind it; yellow-green: the robot where it stood to act.`)));
}

/** A small picture of the tag `epc` (named `name`) for a list row: the newest a robot sent,
 * read from the tag's own picture route so a list never reads every tag's trials. */
export function tagThumbnail(epc, name) {
  const box = h('span', { class: 'thumbnail-box' });
  const image = h('img', {
    src: `/api/v1/tags/${seg(epc)}/picture`, alt: `What a robot last saw at ${name}`, loading: 'lazy',
    class: ['picture', 'thumbnail'],
    // No picture yet (404): nothing to show, rather than a broken image.
    on: { error: () => box.replaceChildren() },
  });
  box.replaceChildren(image);
  return box;
}
