// A small Leaflet control naming the track lines (and dots) by colour, each
// with a switch to hide it where it has one.

import {el} from './dom.js';

const L = window.L;

// An SVG element with these attributes (set as attributes, never parsed as markup).
function svg(tag, attributes) {
  const node = document.createElementNS('http://www.w3.org/2000/svg', tag);
  for (const [key, value] of Object.entries(attributes)) node.setAttribute(key, String(value));
  return node;
}

// entries: [{key, label, color, dashArray, dot, fill, toggle}]; `toggle(on)`: a checkbox shows/hides it.
export function trackLegend(map, entries) {
  const Legend = L.Control.extend({
    options: {position: 'bottomright'},
    onAdd() {
      const box = el('div', {class: 'leaflet-control track-legend', role: 'group', 'aria-label': 'tracks'});
      for (const entry of entries) {
        const swatch = svg('svg', {width: 22, height: 8});
        swatch.append(entry.dot
          ? svg('circle', {cx: 11, cy: 4, r: 3, stroke: entry.color, fill: entry.fill ? entry.color : 'none'})
          : svg('line', {x1: 1, y1: 4, x2: 21, y2: 4, stroke: entry.color, 'stroke-width': 3,
            ...(entry.dashArray ? {'stroke-dasharray': entry.dashArray} : {})}));
        const label = el('span', {class: 'label'}, entry.label);
        const row = entry.toggle
          ? el('label', {class: 'entry', dataset: {track: entry.key}},
            el('input', {type: 'checkbox', checked: true, onchange: event => entry.toggle(event.target.checked)}),
            swatch, label)
          : el('div', {class: 'entry', dataset: {track: entry.key}}, swatch, label);
        box.append(row);
      }
      L.DomEvent.disableClickPropagation(box);
      L.DomEvent.disableScrollPropagation(box);
      return box;
    },
  });
  return new Legend().addTo(map);
}
