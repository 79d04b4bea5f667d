// Why a trial was made, and which trials a success rate counts. Real use by default: an
// experiment's deliberate failures (an unplugged lamp, a stuck drawer) say nothing about how a
// thing works for the people it serves. A caretaker may count experiments and tests on request.

import { h, uid } from './dom.js';
import { recalled, remember } from './preference.js';

// The titles of trial.schema.json's `purpose`, in words for a sentence.
const TITLES = { use: 'Real use', experiment: 'Experiment', test: 'Test' };
const PLURALS = { use: 'real use', experiment: 'experiments', test: 'tests' };

/** A badge beside a trial made for anything but real use; null for real use. */
export function purposeBadge(trial) {
  if (!trial.purpose || trial.purpose === 'use') return null;
  return h('span', { class: 'badge', dataset: { purpose: trial.purpose } }, TITLES[trial.purpose] ?? trial.purpose);
}

const PREFERENCE = 'count-experiments';

/**
 * A checkbox to count experiments and tests too, as this user last left it; `onChange` runs
 * when it is switched.
 */
export function countedControl(onChange) {
  const id = uid('count-experiments');
  const changed = () => {
    remember(PREFERENCE, box.checked ? 'yes' : 'no');
    onChange();
  };
  const box = h('input', { type: 'checkbox', id, checked: recalled(PREFERENCE) === 'yes', on: { change: changed } });
  return {
    element: h('div', { class: 'field checkbox' }, box, h('label', { for: id }, 'Include experiments and tests')),
    /** The stats route's `include` parameter, or null for real use only. */
    include: () => (box.checked ? 'experiment,test' : null),
  };
}

function inWords(items) {
  return items.length <= 1 ? items.join('') : `${items.slice(0, -1).join(', ')} and ${items.at(-1)}`;
}

/** What the numbers count, in a sentence: "Real use only; 48 experiment trials not counted." */
export function countedInWords(stats) {
  const counted = stats.counted ?? ['use'];
  const what = counted.length === 1
    ? 'Real use only'
    : `Counting ${inWords(counted.map((purpose) => PLURALS[purpose] ?? purpose))}`;
  const left = Object.entries(stats.not_counted ?? {}).map(([purpose, trials]) =>
    `${trials} ${(TITLES[purpose] ?? purpose).toLowerCase()} trial${trials === 1 ? '' : 's'}`);
  return left.length > 0 ? `${what}; ${inWords(left)} not counted.` : `${what}.`;
}

/** Why there is no success rate yet, when no counted trial exists. */
export function noCountedTrials(stats) {
  return (stats.counted ?? ['use']).length === 1
    ? 'No trials of real use yet, so no success rates.'
    : 'No trials yet, so no success rates.';
}
