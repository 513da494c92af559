// Measuring: every click adds a point; the path's length (geodesic,
// map.distance) is shown, and with three points or more the area of the
// polygon they enclose (on the local tangent plane: exact enough for a
// survey site). The result can be cleared or copied.

import {$} from './dom.js';
import {formatMetres, localFrame} from './geo.js';

const L = window.L;

export function formatArea(m2) {
  if (m2 >= 1e6) return `${(m2 / 1e6).toFixed(3)} km²`;
  if (m2 >= 100) return `${m2.toFixed(0)} m²`;
  return `${m2.toFixed(2)} m²`;
}

// Shoelace area of lat/lon points, on the tangent plane at the first one.
export function polygonArea(points) {
  if (points.length < 3) return 0;
  const frame = localFrame([points[0].lat, points[0].lng]);
  const xy = points.map(p => frame.toLocal(p.lat, p.lng));
  let twice = 0;
  for (let i = 0; i < xy.length; ++i) {
    const a = xy[i], b = xy[(i + 1) % xy.length];
    twice += a.east * b.north - b.east * a.north;
  }
  return Math.abs(twice) / 2;
}

export class Measure {
  constructor(map) {
    this.map = map;
    this.points = [];
    this.layer = L.featureGroup().addTo(map);
    $('#measure-clear')?.addEventListener('click', () => this.clear());
  }

  click(latlng) {
    this.points.push(latlng);
    this.draw();
  }

  length() {
    let metres = 0;
    for (let i = 1; i < this.points.length; ++i) metres += this.map.distance(this.points[i - 1], this.points[i]);
    return metres;
  }

  draw() {
    this.layer.clearLayers();
    for (const p of this.points) {
      L.circleMarker(p, {radius: 4, color: '#ff4fd8', weight: 2, interactive: false}).addTo(this.layer);
    }
    if (this.points.length < 2) {
      this.show(this.points.length ? 'click the next point' : 'click points to measure');
      return;
    }
    const metres = this.length();
    L.polyline(this.points, {color: '#ff4fd8', weight: 2, dashArray: '4 4', interactive: false})
      .bindTooltip(formatMetres(metres), {permanent: true, direction: 'center', className: 'measure-label'})
      .addTo(this.layer);
    let text = `length ${formatMetres(metres)}`;
    let area;
    if (this.points.length >= 3) {
      area = polygonArea(this.points);
      L.polygon(this.points, {color: '#ff4fd8', weight: 1, fillOpacity: 0.12, dashArray: '2 4', interactive: false})
        .addTo(this.layer);
      text += ` · area ${formatArea(area)}`;
    }
    this.show(text, metres, area);
  }

  show(text, metres, area) {
    const out = $('#measure-text') || $('#measure-result');
    out.textContent = text;
    const box = $('#measure-result');
    if (metres !== undefined) box.dataset.metres = metres.toFixed(3);
    else delete box.dataset.metres;
    if (area !== undefined) box.dataset.area = area.toFixed(3);
    else delete box.dataset.area;
  }

  clear() {
    this.points = [];
    this.layer.clearLayers();
    this.show('click points to measure');
  }
}
