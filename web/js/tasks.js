// Tasks in words, shared by the pages that show them: what is asked, for whom, how it stands.

import { request } from './api.js';
import { when } from './format.js';

/** What asking for `action` reads as on a button: "Ask a robot to turn it off". */
export function askLabel(action) {
  const words = { on: 'turn it on', off: 'turn it off', open: 'open it', close: 'close it', drop: 'drop something in' };
  return `Ask a robot to ${words[action] ?? `do “${action}”`}`;
}

/** Who may do the task. */
export function forWhom(task) {
  if (task.robot) return `robot ${task.robot}`;
  if (task.class) return `any ${task.class} robot`;
  return 'any robot that can';
}

/** "stretch-1", "stretch-1 or el-e-1", "stretch-1, el-e-1 or pr2-1". */
export function eitherOf(robots) {
  if (robots.length <= 1) return robots.join('');
  return `${robots.slice(0, -1).join(', ')} or ${robots[robots.length - 1]}`;
}

/** The task's state as a short phrase and the badge class it is shown with. */
export function stateOf(task) {
  switch (task.state) {
    case 'queued':
      if (task.stuck) return { text: 'no robot can take it now', badge: 'bad' };
      if (task.waiting_for?.length) return { text: `waiting for ${eitherOf(task.waiting_for)}`, badge: 'warn' };
      return { text: task.attempts > 0 ? 'waiting for another robot' : 'waiting for a robot', badge: 'warn' };
    case 'claimed': return { text: `being done by ${task.claimed_by}`, badge: 'warn' };
    case 'done': return { text: `done by ${task.claimed_by}`, badge: 'good' };
    case 'failed': return { text: 'failed', badge: 'bad' };
    case 'cancelled': return task.expired ? { text: 'expired', badge: 'bad' } : { text: 'cancelled', badge: '' };
    default: return { text: String(task.state), badge: '' };
  }
}

/**
 * When the task expires, in words: for a task not yet done, when it will; for one that expired,
 * that no robot did it in time. Null when it has no expiry or ended otherwise.
 */
export function expiryNote(task) {
  if (task.expired) {
    const what = task.trial || task.attempts > 0 ? 'finished' : 'took';
    return `No robot ${what} it before it expired (${when(task.expires_at)}). Ask again if it is still wanted.`;
  }
  if (['queued', 'claimed'].includes(task.state) && task.expires_at) {
    return `Expires ${when(task.expires_at)} unless a robot does it by then.`;
  }
  return null;
}

/** Why a waiting task will not be taken ("stretch-1 declined: …; no other robot can do it"), or null. */
export function stuckReason(task) {
  return task.state === 'queued' && task.stuck ? task.stuck : null;
}

/** Asks the registry for a task; returns the stored task. */
export async function askFor(body) {
  return (await request('POST', '/api/v1/tasks', { body })).data;
}

/** Cancels a task; returns it as it is now. */
export async function cancel(task) {
  return (await request('POST', `/api/v1/tasks/${encodeURIComponent(task.id)}/cancel`)).data;
}
