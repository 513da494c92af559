// Distance between two clicked points (geodesic, map.distance).

import {$} from './dom.js';
import {formatMetres} from './geo.js';

const L = window.L;

export class Measure {
  constructor(map) {
    this.map = map;
    this.points = [];
    this.layer = L.featureGroup().addTo(map);
  }

  click(latlng) {
    if (this.points.length === 2) this.clear();
    this.points.push(latlng);
    L.circleMarker(latlng, {radius: 4, color: '#ff4fd8', weight: 2, interactive: false}).addTo(this.layer);
    if (this.points.length === 2) {
      const [a, b] = this.points;
      const metres = this.map.distance(a, b);
      L.polyline([a, b], {color: '#ff4fd8', weight: 2, dashArray: '4 4', interactive: false})
        .bindTooltip(formatMetres(metres), {permanent: true, direction: 'center', className: 'measure-label'})
        .addTo(this.layer);
      this.show(`${formatMetres(metres)}`, metres);
    } else {
      this.show('click the second point');
    }
  }

  show(text, metres) {
    const out = $('#measure-result');
    out.textContent = text;
    if (metres !== undefined) out.dataset.metres = metres.toFixed(3);
    else delete out.dataset.metres;
  }

  clear() {
    this.points = [];
    this.layer.clearLayers();
    this.show('click two points');
  }
}
