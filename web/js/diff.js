// Field-level differences between versions of an entry: for a tag's history, and for a
// conflict between the revision a caretaker started from, what someone else saved, and theirs.

import { getAt, join, parent, setAt } from './pointer.js';

/** Every leaf of a JSON value by pointer; arrays and empty objects count as leaves. */
export function leaves(value, pointer = '', out = new Map()) {
  if (value !== null && typeof value === 'object' && !Array.isArray(value) && Object.keys(value).length) {
    for (const [key, child] of Object.entries(value)) leaves(child, pointer + join(key), out);
  } else if (pointer !== '' || value !== undefined) {
    out.set(pointer, value);
  }
  return out;
}

const same = (a, b) => JSON.stringify(a) === JSON.stringify(b);

/** The fields that differ from `before` to `after`: [{ pointer, before, after }]. */
export function changes(before, after) {
  const a = leaves(before ?? {});
  const b = leaves(after ?? {});
  const pointers = [...new Set([...a.keys(), ...b.keys()])];
  return pointers
    .filter((pointer) => !same(a.get(pointer), b.get(pointer)))
    .map((pointer) => ({ pointer, before: a.get(pointer), after: b.get(pointer) }));
}

/**
 * What changed since `base` on either side: [{ pointer, base, theirs, mine, conflict }], where
 * `conflict` marks a field both sides changed, differently.
 */
export function threeWay(base, theirs, mine) {
  const pointers = [...new Set([...changes(base, theirs), ...changes(base, mine)].map((c) => c.pointer))];
  return pointers.sort().map((pointer) => {
    const row = { pointer, base: getAt(base, pointer), theirs: getAt(theirs, pointer), mine: getAt(mine, pointer) };
    row.conflict = !same(row.theirs, row.base) && !same(row.mine, row.base) && !same(row.theirs, row.mine);
    return row;
  });
}

/**
 * Their entry with my changes (since `base`) applied on top: where both changed a field, mine
 * wins, and the caretaker reviews the result before saving it.
 */
export function reapply(base, theirs, mine) {
  const merged = structuredClone(theirs);
  for (const { pointer, after } of changes(base, mine)) {
    setAt(merged, pointer, after === undefined ? undefined : structuredClone(after));
    // A whole object I removed goes too, rather than lingering as an empty shell.
    for (let up = parent(pointer); up && after === undefined; up = parent(up)) {
      const left = getAt(merged, up);
      if (getAt(mine, up) !== undefined || !left || typeof left !== 'object' || Object.keys(left).length) break;
      setAt(merged, up, undefined);
    }
  }
  return merged;
}
