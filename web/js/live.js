// What moves while the mission is built or replayed: the vehicle marker
// (rotated by heading), the track line (from /api/track, then `track`
// events) and the progress bar with the mission status.

import {getJSON} from './api.js';
import {$} from './dom.js';
import {formatTime} from './geo.js';

const L = window.L;

export class Vehicle {
  constructor(map) {
    this.map = map;
    this.follow = false;
    this.marker = L.marker([0, 0], {
      icon: L.divIcon({
        className: 'vehicle-icon',
        html: '<svg viewBox="-12 -12 24 24" width="28" height="28"><path d="M0,-11 L7,9 L0,5 L-7,9 Z"/></svg>',
        iconSize: [28, 28],
        iconAnchor: [14, 14],
      }),
      interactive: false,
      keyboard: false,
      zIndexOffset: 1000,
    });
  }

  update(pose) {
    if (!pose) return;
    const latlng = [pose.lat, pose.lon];
    this.marker.setLatLng(latlng);
    if (!this.map.hasLayer(this.marker)) this.marker.addTo(this.map);
    const arrow = this.marker.getElement()?.querySelector('svg');
    if (arrow) arrow.style.transform = `rotate(${pose.heading_deg || 0}deg)`;
    const info = $('#pose');
    if (info) {
      info.textContent = `frame ${pose.frame} · heading ${(pose.heading_deg ?? 0).toFixed(0)}° · ` +
        `depth ${(pose.depth_m ?? 0).toFixed(1)} m · alt ${(pose.altitude_m ?? 0).toFixed(2)} m · t ${formatTime(pose.time_s)}`;
    }
    if (this.follow) this.map.panTo(latlng, {animate: false});
  }
}

export class Track {
  constructor(map) {
    this.map = map;
    this.line = L.polyline([], {color: '#ffb000', weight: 2, opacity: 0.9, interactive: false}).addTo(map);
    this.times = [];
    this.next = 0;          // sequence number of the next point we expect
    this.fetching = null;
  }

  get points() {
    return this.line.getLatLngs();
  }

  async load() {
    const feature = await getJSON('/api/track');
    const coords = feature.geometry ? feature.geometry.coordinates : [];
    this.line.setLatLngs(coords.map(([lon, lat]) => [lat, lon]));
    this.times = (feature.properties && feature.properties.times) || [];
    const from = (feature.properties && feature.properties.from) || 0;
    this.next = coords.length ? from + coords.length : from;
    this.showCount();
  }

  // Fetches the points from the last one we have on (after a gap).
  catchUp() {
    if (this.fetching) return this.fetching;
    this.fetching = (async () => {
      try {
        const feature = await getJSON(`/api/track?since=${this.next}`);
        const coords = feature.geometry ? feature.geometry.coordinates : [];
        const from = feature.properties ? feature.properties.from : this.next - 1;
        const times = (feature.properties && feature.properties.times) || [];
        coords.forEach(([lon, lat], i) => this.add({seq: from + i, lat, lon, time_s: times[i]}, false));
        if (feature.properties && feature.properties.next > this.next && !coords.length) this.next = feature.properties.next;
      } catch (error) {
        console.warn('seamap: track catch-up', error);
      } finally {
        this.fetching = null;
      }
    })();
    return this.fetching;
  }

  add(point, mayCatchUp = true) {
    if (point.seq < this.next) return;                    // already have it
    if (point.seq > this.next && mayCatchUp) {             // missed some
      this.catchUp();
      return;
    }
    this.line.addLatLng([point.lat, point.lon]);
    this.times.push(point.time_s);
    this.next = point.seq + 1;
    this.showCount();
  }

  showCount() {
    const count = $('#track-count');
    const n = this.line.getLatLngs().length;
    count.textContent = String(n);
    count.dataset.count = String(n);
  }

  toGeoJSON() {
    const feature = this.line.toGeoJSON(7);
    feature.properties = {name: 'track', times: this.times};
    return feature;
  }
}

export function showStatus(status) {
  if (!status) return;
  const bar = $('#progress');
  const fraction = Math.max(0, Math.min(1, Number(status.progress) || 0));
  bar.value = fraction;
  bar.dataset.value = fraction.toFixed(4);
  bar.dataset.state = status.state || '';
  const label = $('#progress-label');
  const pct = (fraction * 100).toFixed(0);
  const rate = status.frames_per_s ? ` · ${Number(status.frames_per_s).toFixed(1)} frames/s` : '';
  label.textContent = `${status.state || ''}${status.replay ? ' (replay)' : ''} · ${status.frames_done ?? 0}/${status.frames_total ?? '?'} frames · ${pct}%${rate}`;
  $('#mission-name').textContent = status.name || 'SeaMap';
  const tiles = $('#tiles-written');
  if (tiles) tiles.textContent = `${status.tiles_written ?? 0} tiles written, ${status.frames_rejected ?? 0} frames rejected`;
  document.body.dataset.state = status.state || '';
}
