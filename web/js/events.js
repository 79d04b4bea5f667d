// The registry's live feed (Server-Sent Events at /api/v1/events), shared by every page. The
// browser sends the session cookie with it and reconnects by itself, resuming from the last
// event id.

const EVENT_TYPES = [
  'tag_changed', 'tag_archived', 'tag_retagged', 'trial_recorded', 'trial_updated',
  'robot_changed', 'inbox_changed', 'reliability_changed', 'learned_changed', 'task_changed',
];

let source = null;
const listeners = new Set();

function open() {
  source = new EventSource('/api/v1/events');
  for (const type of EVENT_TYPES) {
    source.addEventListener(type, (event) => {
      let data = {};
      try {
        data = JSON.parse(event.data);
      } catch {
        // An event without JSON still tells that something changed.
      }
      for (const listener of listeners) listener(type, data);
    });
  }
}

/** Calls `listener(type, data)` for every event until the returned function is called. */
export function subscribe(listener) {
  if (!source) open();
  listeners.add(listener);
  return () => listeners.delete(listener);
}

/** Closes the feed (on logout). */
export function closeFeed() {
  source?.close();
  source = null;
  listeners.clear();
}
