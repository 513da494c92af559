// The SLAM keyframes a towed GPS buoy placed (seamap georef's nav.csv, given
// to serve or replay with --georef-nav): a dot each, filled where the
// keyframe was used in the fit (tether taut), hollow where it was dropped;
// around each, a faint circle holding 95 % of its predicted horizontal error
// (sigma_m, 2D RMS: a circular Gaussian's 95 % radius is 1.73 of it), drawn
// to the map's scale, so the operator sees where the placement is weak.

import {getJSON} from './api.js';

const L = window.L;

export const SIGMA_95 = 1.73;  // radius of 95 % over the 2D RMS error, circular Gaussian

export const KEYFRAME_STYLES = {
  good: {label: 'keyframes used in the fit (circle: 95 % of the predicted error)', color: '#39d353', fill: true},
  dropped: {label: 'keyframes dropped (slack tether)', color: '#9aa5ad', fill: false},
};

export class Keyframes {
  constructor(map) {
    this.map = map;
    // Not interactive: a map click under a dot still lists the photos.
    this.layers = {good: L.layerGroup().addTo(map), dropped: L.layerGroup().addTo(map)};
  }

  async load() {
    const collection = await getJSON('/api/keyframes');
    for (const group of Object.values(this.layers)) group.clearLayers();
    for (const feature of collection.features || []) {
      const [lon, lat] = feature.geometry.coordinates;
      const kind = feature.properties.good ? 'good' : 'dropped';
      const style = KEYFRAME_STYLES[kind];
      const sigma = feature.properties.sigma_m;
      if (sigma > 0) {
        L.circle([lat, lon], {radius: SIGMA_95 * sigma, weight: 1, opacity: 0.35, color: style.color, fill: true,
          fillOpacity: 0.08, interactive: false, className: `keyframe-sigma keyframe-sigma-${kind}`})
          .addTo(this.layers[kind]);
      }
      L.circleMarker([lat, lon], {radius: 3, weight: 1, color: style.color, fill: style.fill, fillOpacity: 0.9,
        interactive: false, className: `keyframe keyframe-${kind}`}).addTo(this.layers[kind]);
    }
  }

  count(kind) {
    return this.layers[kind].getLayers().filter(l => !(l instanceof L.Circle)).length;
  }

  setVisible(kind, visible) {
    if (visible) this.layers[kind].addTo(this.map);
    else this.layers[kind].remove();
  }
}
