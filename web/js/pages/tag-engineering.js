// What a robot engineer looks for on a tag's page, behind the advanced section: the EPC and
// its URI, which behaviour does each action, every behaviour parameter and per-robot
// override, the colour settings per robot, and the entry as JSON. Labels come from the
// schemas' titles; values are shown as stored.

import { entryOf } from '../api.js';
import { h } from '../dom.js';
import { when } from '../format.js';
import { choicesOf, labelOf, propertiesOf, titleOf, unitOf } from '../schema.js';

/** A parameter's value with its unit, e.g. "0.08 m", "Press a rocker switch". */
function valueText(prop, value) {
  if (choicesOf(prop ?? {}).length) return titleOf(prop, value);
  if (typeof value === 'boolean') return value ? 'yes' : 'no';
  if (typeof value === 'object') return JSON.stringify(value);
  const unit = prop ? unitOf(prop) : null;
  return `${value}${unit ? (unit === '°' ? unit : ` ${unit}`) : ''}`;
}

function parameterList(params, values) {
  const shown = Object.entries(values ?? {}).filter(([name]) => !['behavior', 'robots'].includes(name));
  if (shown.length === 0) return h('p', { class: 'muted' }, 'All parameters at their defaults.');
  return h('dl', { class: 'params' }, shown.map(([name, value]) => [
    h('dt', {}, labelOf(name, params[name] ?? {}), h('code', { class: 'param-key' }, name)),
    h('dd', {}, valueText(params[name], value))]));
}

function behaviorsView(tag, schemas) {
  const behaviorTitles = schemas.tag.$defs?.behavior_name ?? {};
  return Object.entries(tag.behaviors ?? {}).map(([key, spec]) => {
    const doc = schemas.behaviors[spec.behavior];
    const params = doc ? propertiesOf(doc, doc) : {};
    const actions = Object.entries(tag.actions ?? {}).filter(([, target]) => target === key).map(([action]) => action);
    return h('div', { class: 'behavior', dataset: { behavior: key } },
      h('h4', {}, h('code', {}, key), ` · ${titleOf(behaviorTitles, spec.behavior)} (`, h('code', {}, spec.behavior), ')'),
      h('p', { class: 'muted' }, actions.length ? `Runs the actions ${actions.join(', ')}.` : 'No action runs it.'),
      parameterList(params, spec),
      Object.entries(spec.robots ?? {}).map(([robot, override]) => h('div', {},
        h('h5', {}, `Override for ${robot}`), parameterList(params, override))));
  });
}

function colourView(tag, schemas) {
  const overrides = Object.entries(tag.properties?.robots ?? {});
  if (overrides.length === 0) return h('p', { class: 'muted' }, 'No per-robot properties: every robot uses the defaults.');
  const segmentation = schemas.tag.$defs?.color_segmentation?.properties ?? {};
  return h('ul', {}, overrides.map(([robot, props]) => h('li', {},
    h('strong', {}, robot), ': ',
    Object.entries(props).map(([name, value]) => (name === 'color_segmentation' && value && typeof value === 'object'
      ? Object.entries(value).map(([k, range]) => `${labelOf(k, segmentation[k] ?? {})} ${Array.isArray(range) ? range.join('–') : range}`).join(', ')
      : `${name} ${JSON.stringify(value)}`)).join('; '))));
}

/** The engineering view of `tag` (as GET returns it). */
export function engineeringView(tag, schemas) {
  return [
    h('h3', {}, 'Identity'),
    h('dl', { class: 'facts' },
      h('dt', {}, 'EPC'), h('dd', {}, h('code', { class: 'epc' }, tag.epc)),
      h('dt', {}, 'EPC URI'), h('dd', {}, tag.epc_uri ? h('span', { class: 'uri' }, tag.epc_uri) : 'none (the EPC does not decode)'),
      h('dt', {}, 'Kind'), h('dd', {}, h('code', {}, tag.properties?.type ?? '—')),
      h('dt', {}, 'Revision'), h('dd', {}, `${tag.revision}, saved by ${tag.updated_by ?? '—'} · ${when(tag.updated_at)}`)),
    h('h3', {}, 'Behaviours and their parameters'),
    behaviorsView(tag, schemas),
    h('h3', {}, 'Colour settings and other per-robot properties'),
    colourView(tag, schemas),
    h('details', { class: 'json-view' }, h('summary', {}, 'The entry as JSON'),
      h('pre', { class: 'json small' }, JSON.stringify(entryOf(tag), null, 2))),
  ];
}
