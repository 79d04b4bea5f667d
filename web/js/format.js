// How values read on screen: times, rates, outcomes.

const dateTime = new Intl.DateTimeFormat(undefined, { dateStyle: 'medium', timeStyle: 'short' });

/** A timestamp for people, or an em dash when there is none. */
export function when(iso) {
  if (!iso) return '—';
  const date = new Date(iso);
  return Number.isNaN(date.getTime()) ? String(iso) : dateTime.format(date);
}

/** "3 min ago", for recent times; the full time otherwise. */
export function ago(iso) {
  if (!iso) return 'never';
  const seconds = (Date.now() - new Date(iso).getTime()) / 1000;
  if (Number.isNaN(seconds)) return String(iso);
  if (seconds < 60) return 'just now';
  if (seconds < 3600) return `${Math.round(seconds / 60)} min ago`;
  if (seconds < 86400) return `${Math.round(seconds / 3600)} h ago`;
  return when(iso);
}

/** A rate 0..1 as a percentage, or an em dash when unknown. */
export function percent(rate) {
  return typeof rate === 'number' ? `${Math.round(rate * 100)} %` : '—';
}

/** A JSON value as short text for tables and diffs. */
export function short(value) {
  if (value === undefined) return '(not set)';
  if (typeof value === 'string') return value;
  return JSON.stringify(value);
}

/** The person's verdict on a trial. */
export function verdict(confirmed) {
  if (confirmed === true) return 'worked';
  if (confirmed === false) return 'did not work';
  return 'not asked';
}

/** A JSON pointer as a readable field path: "/behaviors/push_top/force_threshold" → "behaviors › push_top › force_threshold". */
export function fieldPath(pointer) {
  if (!pointer) return 'the entry';
  return pointer.split('/').slice(1).map((part) => part.replaceAll('~1', '/').replaceAll('~0', '~')).join(' › ');
}

/** How good a success rate is, as the badge class it is shown with: green from 90 % (the
 * reliability rule's bar), amber from 60 %, red below. */
export function grade(rate) {
  if (typeof rate !== 'number') return '';
  if (rate >= 0.9) return 'good';
  if (rate >= 0.6) return 'warn';
  return 'bad';
}
