// The SLAM keyframes a towed GPS buoy placed (seamap georef's nav.csv, given
// to serve or replay with --georef-nav): a dot each, filled where the
// keyframe was used in the fit (tether taut), hollow where it was dropped.

import {getJSON} from './api.js';

const L = window.L;

export const KEYFRAME_STYLES = {
  good: {label: 'keyframes used in the fit', color: '#39d353', fill: true},
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
      L.circleMarker([lat, lon], {radius: 3, weight: 1, color: style.color, fill: style.fill, fillOpacity: 0.9,
        interactive: false, className: `keyframe keyframe-${kind}`}).addTo(this.layers[kind]);
    }
  }

  count(kind) {
    return this.layers[kind].getLayers().length;
  }

  setVisible(kind, visible) {
    if (visible) this.layers[kind].addTo(this.map);
    else this.layers[kind].remove();
  }
}
