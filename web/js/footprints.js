// The footprints layer: each frame's outline on the seabed (from
// /api/footprints for the view, fetched again when the view moves or, while
// the map builds, every few seconds); a click on one opens its photo. Off by
// default: on a weak link it costs a request per view.

import {getJSON} from './api.js';
import {$, toast} from './dom.js';

const L = window.L;
const REFRESH_MS = 10000;

export class Footprints {
  // openFrame(id): shows frame `id` in the photo viewer.
  constructor(map, openFrame) {
    this.map = map;
    this.openFrame = openFrame;
    this.layer = L.geoJSON(null, {
      style: {color: '#7cffb2', weight: 1, fillOpacity: 0.03, className: 'footprint'},
      onEachFeature: (feature, path) => {
        path.on('click', event => {
          if (document.body.dataset.mode !== 'photos') return;   // measuring or marking: the map's click
          L.DomEvent.stopPropagation(event);
          this.openFrame(feature.properties.id);
        });
        // A node, not a string (Leaflet writes a string as HTML): the file name shows as typed.
        path.bindTooltip(() => document.createTextNode(String(feature.properties.image || `frame ${feature.id}`)),
          {sticky: true});
      },
    });
    this.on = false;
    this.request = 0;
    const box = $('#footprints');
    box.addEventListener('change', () => this.show(box.checked));
    map.on('moveend', () => { if (this.on) this.load(); });
    setInterval(() => { if (this.on && this.building) this.load(); }, REFRESH_MS);
    this.building = false;
  }

  show(on) {
    this.on = Boolean(on);
    $('#footprints').checked = this.on;
    if (this.on) {
      this.layer.addTo(this.map);
      this.load();
    } else {
      this.map.removeLayer(this.layer);
    }
  }

  async load() {
    const request = ++this.request;
    const b = this.map.getBounds().pad(0.2);
    const clamp = (v, lo, hi) => Math.max(lo, Math.min(hi, v));
    const bbox = [clamp(b.getWest(), -180, 180), clamp(b.getSouth(), -90, 90), clamp(b.getEast(), -180, 180),
      clamp(b.getNorth(), -90, 90)].map(v => v.toFixed(7)).join(',');
    try {
      const collection = await getJSON(`/api/footprints?bbox=${bbox}`);
      if (request !== this.request || !this.on) return;
      this.layer.clearLayers();
      this.layer.addData(collection);
      this.count = collection.features.length;
      $('#footprints').dataset.count = String(this.count);
    } catch (error) {
      if (request === this.request) toast(`footprints: ${error.message}`);
    }
  }
}
