// The registry's JSON Schemas, read from GET /api/v1/schema/{name}: the one source of the
// form's fields, units, help lines, defaults and bounds. The UI keeps no rules of its own; it
// asks the registry to validate (POST /api/v1/validate/tag).

import { get } from './api.js';

let loaded = null;

/**
 * The tag and trial schemas and one schema per robot behaviour: `{ tag, trial, behaviors:
 * {name: schema}, behaviorNames }`. The behaviour names come from the tag schema itself.
 */
export function loadSchemas() {
  loaded ??= (async () => {
    const [tag, trial] = await Promise.all([get('/api/v1/schema/tag'), get('/api/v1/schema/trial')]);
    const behaviorNames = choicesOf(tag.$defs?.behavior_name ?? {}).map(([name]) => name);
    const docs = await Promise.all(behaviorNames.map((name) => get(`/api/v1/schema/${encodeURIComponent(name)}`)));
    const behaviors = Object.fromEntries(behaviorNames.map((name, i) => [name, docs[i]]));
    return { tag, trial, behaviors, behaviorNames };
  })();
  loaded.catch(() => { loaded = null; });
  return loaded;
}

/** Follows a local `$ref` ("#/$defs/x"), keeping the referring node's own keywords on top. */
export function deref(doc, node, depth = 0) {
  if (!node || typeof node.$ref !== 'string' || !node.$ref.startsWith('#/') || depth > 10) return node ?? {};
  const target = node.$ref.slice(2).split('/').reduce((at, part) => at?.[part], doc);
  const { $ref, ...own } = node;
  return { ...deref(doc, target, depth + 1), ...own };
}

/** The properties a schema node declares, its own first, then those of its `$ref` and `allOf`. */
export function propertiesOf(doc, node, depth = 0) {
  if (!node || depth > 10) return {};
  const own = node.properties ?? {};
  const viaRef = typeof node.$ref === 'string' && node.$ref.startsWith('#/')
    ? propertiesOf(doc, node.$ref.slice(2).split('/').reduce((at, part) => at?.[part], doc), depth + 1)
    : {};
  const viaAllOf = (node.allOf ?? []).map((part) => propertiesOf(doc, part, depth + 1));
  const merged = { ...own };
  for (const extra of [viaRef, ...viaAllOf]) {
    for (const [key, value] of Object.entries(extra)) if (!(key in merged)) merged[key] = value;
  }
  return Object.fromEntries(Object.entries(merged).map(([key, value]) => [key, deref(doc, value)]));
}

/** The `required` list of a schema node, including its local `$ref`'s. */
export function requiredOf(doc, node) {
  return [...(node?.required ?? []), ...(deref(doc, { $ref: node?.$ref }).required ?? [])];
}

/**
 * The values a property allows, each with its title: `[[value, title]]`. The schemas give
 * them as `oneOf` of `{const, title}`; a plain `enum` (no titles) reads as its values.
 */
export function choicesOf(prop) {
  if (Array.isArray(prop.oneOf) && prop.oneOf.length && prop.oneOf.every((choice) => 'const' in choice)) {
    return prop.oneOf.map((choice) => [choice.const, choice.title ?? String(choice.const)]);
  }
  return Array.isArray(prop.enum) ? prop.enum.map((value) => [value, String(value)]) : [];
}

/**
 * The title the schema gives `value` of `prop`: from its choices, or from `x-titles` where
 * values are open (device kinds, action names); else the value in words ("push_top" → "Push
 * top").
 */
export function titleOf(prop, value) {
  const known = choicesOf(prop ?? {}).find(([v]) => v === value)?.[1] ?? prop?.['x-titles']?.[value];
  return known ?? sentence(String(value ?? '').replaceAll('_', ' '));
}

/** The titles a caretaker reads for a tag's kind, one of its actions and a robot behaviour. */
export function titlesFrom(schemas) {
  return {
    kind: (type) => titleOf(schemas.tag.$defs.properties.properties.type, type),
    action: (action) => titleOf(schemas.tag.properties.actions, action),
    behavior: (name) => titleOf(schemas.tag.$defs.behavior_name, name),
  };
}

const sentence = (text) => text.charAt(0).toUpperCase() + text.slice(1);

/** What kind of control a property needs. */
export function kindOf(prop) {
  if ('const' in prop) return 'const';
  if (choicesOf(prop).length) return 'enum';
  if (prop.type === 'number' || prop.type === 'integer') return 'number';
  if (prop.type === 'boolean') return 'boolean';
  if (prop.type === 'string') return 'string';
  if (prop.type === 'object' && prop.properties) return 'object';
  return 'json';
}

/** The unit a property is measured in, from `x-unit`. */
export function unitOf(prop) {
  const unit = prop['x-unit'];
  return unit === 'degrees' ? '°' : unit ?? null;
}

/** The allowed range in words, e.g. "above 0 and at most 20 N". */
export function boundsOf(prop) {
  const unit = prop['x-unit'] ? ` ${prop['x-unit']}` : '';
  const low = prop.exclusiveMinimum !== undefined ? `above ${prop.exclusiveMinimum}`
    : prop.minimum !== undefined ? `at least ${prop.minimum}` : null;
  const high = prop.exclusiveMaximum !== undefined ? `below ${prop.exclusiveMaximum}`
    : prop.maximum !== undefined ? `at most ${prop.maximum}` : null;
  if (!low && !high) return null;
  return `${[low, high].filter(Boolean).join(' and ')}${unit}`;
}

/** The help line of a property: its description, its bounds and its default. */
export function helpOf(prop) {
  const parts = [prop.description];
  const bounds = boundsOf(prop);
  if (bounds) parts.push(`Allowed: ${bounds}.`);
  if (prop.default !== undefined) {
    const value = choicesOf(prop).length ? titleOf(prop, prop.default) : JSON.stringify(prop.default);
    parts.push(`Default: ${value}${prop['x-unit'] ? ` ${prop['x-unit']}` : ''}.`);
  }
  return parts.filter(Boolean).join(' ');
}

/** A field's label: its title, else its key in words ("force_threshold" → "Force threshold"). */
export function labelOf(key, prop = {}) {
  return sentence(prop.title ?? key.replaceAll('_', ' '));
}

/** Whether a property applies to a kind of device (`x-kinds` lists those it is for). */
export function appliesTo(prop, type) {
  return !Array.isArray(prop['x-kinds']) || prop['x-kinds'].includes(type);
}

/**
 * The keys of an object property in the order people read them (`x-order`: width before
 * height), the rest after; the registry serves a schema's keys alphabetically.
 */
export function orderedKeys(prop, keys) {
  const order = Array.isArray(prop['x-order']) ? prop['x-order'] : [];
  const rank = (key) => (order.includes(key) ? order.indexOf(key) : order.length);
  return [...keys].sort((a, b) => rank(a) - rank(b));
}
