// The seabed relief: the mission's height model drawn as a colour relief with
// a hillshade (tiles of the layer "relief", made at build time), a legend
// with the heights of the colour ramp's ends while it is on, and the height
// under a click from /api/terrain.

import {getJSON, missionUrl} from './api.js';
import {el} from './dom.js';

const L = window.L;

// The ramp's stops, low to high: core/terrain/relief_shading.cc's kReliefRampRgb.
export const RELIEF_RAMP = ['#21318c', '#2c7bb6', '#4eb3a0', '#a6d96a', '#f0c86e', '#a6611a'];

const DATUM_TEXT = {sea_surface: 'from the sea surface', mean_seabed: 'from the mean seabed'};

// tilejson.seamap_relief as the server gives it (a JSON string, or already an object); null when none.
export function reliefInfo(tilejson) {
  const value = tilejson && tilejson.seamap_relief;
  if (!value) return null;
  try {
    const info = typeof value === 'string' ? JSON.parse(value) : value;
    return Number.isFinite(info.low_m) && Number.isFinite(info.high_m) ? info : null;
  } catch {
    return null;
  }
}

export const formatHeight = metres => `${metres.toFixed(2)} m`;

export class Relief {
  // `tilejson`: the main map's; the relief tiles are in its format.
  constructor(map, tilejson) {
    this.map = map;
    this.info = reliefInfo(tilejson);
    this.on = false;
    this.legend = null;
    this.popup = null;
    if (!this.info) return;
    const maxZoom = map.getMaxZoom();
    this.layer = L.tileLayer(missionUrl(`/tiles/relief/{z}/{x}/{y}.${tilejson.format || 'png'}`), {
      minNativeZoom: this.info.minzoom ?? 0,
      maxNativeZoom: this.info.maxzoom ?? 22,
      maxZoom: Number.isFinite(maxZoom) ? maxZoom : 25,
      opacity: 0.85,
      zIndex: 5,   // above the photo layers
      className: 'relief-tiles',
      attribution: 'relief: SeaMap height model',
    });
  }

  get available() { return Boolean(this.info); }

  // The switch in the panel's View section.
  bindCheckbox(box, row) {
    row.hidden = !this.available;
    box.addEventListener('change', () => this.show(box.checked));
    this.checkbox = box;
  }

  show(on) {
    if (!this.available) return;
    this.on = Boolean(on);
    if (this.checkbox) this.checkbox.checked = this.on;
    if (this.on) {
      this.layer.addTo(this.map);
      this.legend = this.makeLegend().addTo(this.map);
    } else {
      this.layer.remove();
      this.legend?.remove();
      this.legend = null;
      this.popup?.remove();
    }
  }

  makeLegend() {
    const {low_m: low, high_m: high, datum} = this.info;
    const Legend = L.Control.extend({
      options: {position: 'bottomright'},   // bottom left holds the cursor readout
      onAdd: () => {
        const bar = el('div', {class: 'ramp', style: `background: linear-gradient(to right, ${RELIEF_RAMP.join(', ')})`});
        this.readout = el('div', {class: 'readout', id: 'relief-height'}, 'click the map for the height');
        const box = el('div', {class: 'leaflet-control relief-legend', id: 'relief-legend', role: 'group',
          'aria-label': 'relief legend', dataset: {low: String(low), high: String(high), datum}},
        el('div', {class: 'title'}, `seabed height, m ${DATUM_TEXT[datum] || ''}`.trim()),
        bar,
        el('div', {class: 'ends'}, el('span', {class: 'low'}, formatHeight(low)), el('span', {class: 'high'}, formatHeight(high))),
        this.readout);
        L.DomEvent.disableClickPropagation(box);
        return box;
      },
    });
    return new Legend();
  }

  // The height at a clicked point: in the legend and a popup there.
  async at(latlng) {
    if (!this.on) return null;
    const query = `/api/terrain?lat=${latlng.lat.toFixed(8)}&lon=${latlng.lng.toFixed(8)}`;
    let text;
    let answer = null;
    try {
      answer = await getJSON(query);
      text = `${formatHeight(answer.height_m)} ± ${answer.sigma_m.toFixed(3)} m ${DATUM_TEXT[answer.datum] || ''}`.trim();
    } catch (error) {
      text = error.status === 404 ? 'no height here' : `height: ${error.message}`;
    }
    if (this.readout) {
      this.readout.textContent = text;
      this.readout.dataset.height = answer ? String(answer.height_m) : '';
    }
    this.popup = L.popup({className: 'relief-popup', autoPan: false}).setLatLng(latlng)
      .setContent(el('span', {class: 'relief-height'}, text)).openOn(this.map);
    return answer;
  }
}
