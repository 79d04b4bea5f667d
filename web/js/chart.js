// A small bar chart of success rates per action and robot class, as inline SVG built with DOM
// calls. Each row is a label line over a full-width bar, so it stays legible on a phone; the
// numbers are in the text too, so it reads without the bars. A bar's colour says how good the
// rate is (green, amber, red), the same grades as the caretaker's summary.

import { svg } from './dom.js';
import { grade, percent } from './format.js';

const WIDTH = 320;
const ROW = 46;
const BAR = 14;

/** The chart for the `groups` of GET /api/v1/tags/{epc}/stats. */
export function successChart(groups) {
  const height = Math.max(groups.length, 1) * ROW;
  const summary = groups
    .map((g) => `${g.action} by ${g.robot_class ?? 'any robot'}: ${percent(g.success_rate)} of ${g.attempts}`)
    .join('; ');
  const chart = svg('svg', {
    class: 'chart', viewBox: `0 0 ${WIDTH} ${height}`, role: 'img', 'aria-label': `Success rate per action. ${summary}`,
  }, svg('title', {}, 'Success rate per action'));
  groups.forEach((group, i) => {
    const top = i * ROW;
    const rate = typeof group.success_rate === 'number' ? Math.max(0, Math.min(1, group.success_rate)) : 0;
    chart.append(
      svg('text', { x: 0, y: top + 16, class: 'chart-label' }, `${group.action} · ${group.robot_class ?? 'any robot'}`),
      svg('text', { x: WIDTH, y: top + 16, class: 'chart-value', 'text-anchor': 'end' },
        `${percent(group.success_rate)} of ${group.attempts}${group.reliable ? ' · reliable' : ''}`),
      svg('rect', { x: 0, y: top + 24, width: WIDTH, height: BAR, rx: 4, class: 'chart-track' }),
      svg('rect', { x: 0, y: top + 24, width: Math.round(rate * WIDTH), height: BAR, rx: 4, class: `chart-bar ${grade(group.success_rate)}` }));
  });
  return chart;
}
