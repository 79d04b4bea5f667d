// A tag's trial history, newest first by when each started (robots may upload late, from their
// outbox, so the order of receipt is not the order of time): when, which robot, which action, what the robot's
// detector said, what the person said, and the evidence. A caretaker can give their verdict.
// Actions, outcomes and robots are named in words (`words`, from the schemas' titles).

import { getAll, query, request, seg } from '../api.js';
import { cell, h, replace } from '../dom.js';
import { verdict, when } from '../format.js';
import { purposeBadge } from '../purpose.js';
import { trialPicture } from '../picture.js';

/** Fills `container` with the trials of `epc`; returns them, in the order they arrived. */
export async function renderTrials(container, epc, words) {
  const trials = await getAll(`/api/v1/trials${query({ epc, include: 'forces', limit: 500 })}`);
  if (trials.length === 0) {
    replace(container, h('p', { class: 'muted' }, 'No robot has tried this tag yet.'));
    return trials;
  }
  const started = (trial) => Date.parse(trial.started_at ?? trial.finished_at) || 0;
  const newestFirst = trials.slice().sort((a, b) => started(b) - started(a) || (b.seq ?? 0) - (a.seq ?? 0));
  const rows = newestFirst.map((trial) => trialRow(trial, words, () => renderTrials(container, epc, words)));
  replace(container, h('table', { class: 'trials responsive' },
    h('caption', { class: 'visually-hidden' }, 'Trials, newest first'),
    h('thead', {}, h('tr', {}, ['When', 'Robot', 'Action', 'Outcome', 'Verdict', 'Evidence'].map((label) => h('th', { scope: 'col' }, label)))),
    h('tbody', {}, rows)));
  return trials;
}

function trialRow(trial, words, refresh) {
  const verdictBox = h('div', {}, h('span', { class: 'verdict' }, verdict(trial.confirmed)));
  if (trial.confirmed === null || trial.confirmed === undefined) {
    const answer = (confirmed) => async (event) => {
      event.target.disabled = true;
      try {
        await request('PATCH', `/api/v1/trials/${seg(trial.id)}`, { body: { confirmed } });
        refresh();
      } catch (error) {
        verdictBox.append(h('p', { class: 'field-error', role: 'alert' }, error.message));
        event.target.disabled = false;
      }
    };
    verdictBox.append(h('div', { class: 'verdict-buttons' },
      h('button', { type: 'button', class: 'small secondary', on: { click: answer(true) }, 'aria-label': `Trial at ${when(trial.finished_at)} worked` }, 'It worked'),
      h('button', { type: 'button', class: 'small secondary', on: { click: answer(false) }, 'aria-label': `Trial at ${when(trial.finished_at)} did not work` }, 'It did not')));
  }
  const forces = Array.isArray(trial.forces) ? trial.forces.length : 0;
  const evidence = { detector: trial.detector, measurements: trial.measurements, start_pose: trial.start_pose };
  return h('tr', { dataset: { trial: trial.id } },
    cell('When', when(trial.started_at ?? trial.finished_at), trialPicture(trial, { thumbnail: true })),
    cell('Robot', words.robot(trial.robot)),
    cell('Action', words.action(trial.action), purposeBadge(trial)),
    cell('Outcome', h('span', { class: ['badge', trial.outcome === 'success' ? 'good' : 'bad'], dataset: { outcome: trial.outcome } }, words.outcome(trial.outcome))),
    cell('Verdict', verdictBox),
    cell('Evidence', h('details', {},
      h('summary', {}, `What the robot measured (${forces} force samples)`),
      h('pre', { class: 'json small' }, JSON.stringify(evidence, null, 2)))));
}
