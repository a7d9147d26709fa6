// The numbers a person glances at and a test reads: each is an element `stat-NAME` with its value in the
// `data-value` attribute and as text, and the same values are in `window.hoidslamViewer` for scripts
// (docs/viewer.md, "What a test reads from the page").
import { element, setText, formatCount } from './dom.js';

// `frame`: a number of the frame panel, left out of a page without one.
const STATS = [
  { name: 'frame', label: 'frame', frame: true },
  { name: 'state', label: 'tracking', frame: true },
  { name: 'kept', label: 'kept', count: true, frame: true },
  { name: 'dropped', label: 'dropped', count: true, frame: true },
  { name: 'points', label: 'points', count: true, title: 'points of the main map' },
  { name: 'keyframes', label: 'keyframes', count: true, title: 'keyframes of the main map' },
  { name: 'maps', label: 'maps' },
  { name: 'dense', label: 'dense triangles', count: true, title: 'triangles of the dense map drawn (0: hidden)' },
  { name: 'run', label: 'run' },
  { name: 'updates', label: 'frames drawn', count: true, frame: true },
];

export class Stats {
  /** `frames`: whether the page has a frame panel to fill the frame's numbers. */
  constructor(parent, { frames }) {
    this.values = {};
    this.valueElements = new Map();
    const list = element('dl', { className: 'stats' });
    for (const stat of STATS.filter((s) => frames || !s.frame)) {
      const value = element('dd', { text: '–' });
      value.id = `stat-${stat.name}`;
      value.dataset.value = '';
      this.valueElements.set(stat.name, { node: value, count: Boolean(stat.count) });
      this.values[stat.name] = null;
      list.append(element('div', { title: stat.title ?? '' }, [element('dt', { text: stat.label }), value]));
    }
    parent.append(list);
    window.hoidslamViewer = this.values;
  }

  /** Shows one value (called while drawing); null shows as not known yet. */
  set(name, value) {
    const { node, count } = this.valueElements.get(name);
    this.values[name] = value;
    const attribute = value === null ? '' : String(value);
    if (node.dataset.value !== attribute) node.dataset.value = attribute;
    setText(node, count ? formatCount(value) : (attribute || '–'));
  }
}
