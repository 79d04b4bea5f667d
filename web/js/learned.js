// Values the registry learned from a kind of robot's trials, in words: "pull distance 0.32 m,
// learned from 5 trials" rather than the stats' {"value": 0.316, "trials": 5}.

/** The unit a parameter's name implies (the behaviour schemas name them so). */
function unitOf(name) {
  if (/_deg$|degrees?$/.test(name)) return ' °';
  if (/force|threshold$/.test(name)) return ' N';
  if (/distance|height|offset|travel|depth|width|_m$/.test(name)) return ' m';
  return '';
}

/** A number shown to a person: at most three decimals, no trailing zeros. */
function number(value) {
  return typeof value === 'number' ? String(Math.round(value * 1000) / 1000) : String(value);
}

/** The parameter a learned value's JSON pointer names, e.g. /behaviors/pull_open/pull_distance. */
export function parameterOf(pointer) {
  const parts = String(pointer).split('/');
  return (parts[parts.length - 1] ?? '').replaceAll('~1', '/').replaceAll('~0', '~');
}

/** One learned value in words. */
export function learnedInWords(pointer, learned) {
  const name = parameterOf(pointer);
  const value = learned && typeof learned === 'object' ? learned.value : learned;
  const trials = learned && typeof learned === 'object' ? learned.trials : undefined;
  const from = typeof trials === 'number' ? `, learned from ${trials} trial${trials === 1 ? '' : 's'}` : '';
  return `${name.replaceAll('_', ' ')} ${number(value)}${unitOf(name)}${from}`;
}

/** Metres as a person says a tag's side: whole centimetres, to the half below 10 cm, e.g.
 * 0.163 → "16", 0.056 → "5.5". */
function centimetres(metres) {
  const cm = metres * 100;
  return String(cm < 10 ? Math.round(cm * 2) / 2 : Math.round(cm));
}

/** A tag's size in centimetres, e.g. "16 × 24 cm". */
export function sizeInCentimetres(size) {
  return `${centimetres(size.width)} × ${centimetres(size.height)} cm`;
}

/**
 * The size the robots learned a tag to have (the stats' `learned_size`), in words: "Seen by the
 * robots: about 16 × 24 cm, from 4 confirmed visits"; null when none was learned.
 */
export function learnedSizeInWords(learned) {
  if (!learned || typeof learned.width !== 'number' || typeof learned.height !== 'number') return null;
  const visits = `${learned.trials} confirmed visit${learned.trials === 1 ? '' : 's'}`;
  return `Seen by the robots: about ${sizeInCentimetres(learned)}, from ${visits}`;
}
