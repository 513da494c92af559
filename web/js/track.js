// One track line from one source of /api/track: "estimated" (where the frames
// were placed) or "nav" (the navigation's positions). Loaded once, then grown
// by `track` events; a gap in `seq` fetches the missing piece (`?since=`).

import {getJSON} from './api.js';

const L = window.L;

// Where a `track` event's point lies in this source's line.
const positionOf = (point, source) => (source === 'nav' && point.nav ? point.nav : point);

export class Track {
  // options: {source: 'estimated'|'nav', color, dashArray, onCount(n)}
  constructor(map, {source = 'estimated', color = '#ffb000', dashArray = null, onCount = null} = {}) {
    this.map = map;
    this.source = source;
    this.onCount = onCount;
    this.line = L.polyline([], {color, dashArray, weight: 2, opacity: 0.9, interactive: false,
      className: `track track-${source}`}).addTo(map);
    this.times = [];
    this.next = 0;          // sequence number of the next point we expect
    this.fetching = null;
    this.pending = null;    // points that came while loading, added after it
  }

  get points() {
    return this.line.getLatLngs();
  }

  get color() {
    return this.line.options.color;
  }

  url(since) {
    const query = new URLSearchParams({source: this.source});
    if (since !== undefined) query.set('since', String(since));
    return `/api/track?${query}`;
  }

  async load() {
    this.pending = [];
    try {
      const feature = await getJSON(this.url());
      const coords = feature.geometry ? feature.geometry.coordinates : [];
      this.line.setLatLngs(coords.map(([lon, lat]) => [lat, lon]));
      this.times = (feature.properties && feature.properties.times) || [];
      const from = (feature.properties && feature.properties.from) || 0;
      this.next = coords.length ? from + coords.length : from;
      this.showCount();
    } finally {
      const pending = this.pending;
      this.pending = null;
      for (const point of pending) this.add(point);
    }
  }

  // Fetches the points from the last one we have on (after a gap).
  catchUp() {
    if (this.fetching) return this.fetching;
    this.fetching = (async () => {
      try {
        const feature = await getJSON(this.url(this.next));
        const coords = feature.geometry ? feature.geometry.coordinates : [];
        const from = feature.properties ? feature.properties.from : this.next - 1;
        const times = (feature.properties && feature.properties.times) || [];
        coords.forEach(([lon, lat], i) => this.add({seq: from + i, lat, lon, time_s: times[i]}, false));
        if (feature.properties && feature.properties.next > this.next && !coords.length) this.next = feature.properties.next;
      } catch (error) {
        console.warn(`seamap: ${this.source} track catch-up`, error);
      } finally {
        this.fetching = null;
      }
    })();
    return this.fetching;
  }

  // A `track` event's point ({seq, lat, lon, time_s, nav}), or one of ours.
  add(point, mayCatchUp = true) {
    if (this.pending) {                                    // loading: after it
      this.pending.push(point);
      return;
    }
    if (point.seq < this.next) return;                    // already have it
    if (point.seq > this.next && mayCatchUp) {             // missed some
      this.catchUp();
      return;
    }
    const at = positionOf(point, this.source);
    this.line.addLatLng([at.lat, at.lon]);
    this.times.push(point.time_s);
    this.next = point.seq + 1;
    this.showCount();
  }

  setVisible(visible) {
    if (visible) this.line.addTo(this.map);
    else this.line.remove();
  }

  showCount() {
    if (this.onCount) this.onCount(this.line.getLatLngs().length);
  }

  toGeoJSON() {
    const feature = this.line.toGeoJSON(7);
    feature.properties = {name: `track (${this.source})`, times: this.times};
    return feature;
  }
}
