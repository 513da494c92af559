// The mission's track lines: the estimated one (where the frames were placed)
// always; once the status says the trajectory was corrected, the
// navigation's beside it in another colour; for a mission georeferenced by a
// towed GPS buoy, the buoy's track and the keyframes (used in the fit or
// dropped) when the server was given them. A legend names every line shown
// beside the vehicle's, with a switch to hide each.

import {toast, $} from './dom.js';
import {KEYFRAME_STYLES, Keyframes} from './keyframes.js';
import {Track} from './track.js';
import {trackLegend} from './track_legend.js';

export const TRACK_STYLES = {
  estimated: {label: 'estimated (corrected)', color: '#ffb000'},
  nav: {label: 'navigation (raw)', color: '#3ad1ff', dashArray: '6 5'},
  buoy: {label: 'GPS buoy', color: '#d77bff', dashArray: '2 4'},
};

function showCount(n) {
  const count = $('#track-count');
  count.textContent = String(n);
  count.dataset.count = String(n);
}

export class Tracks {
  constructor(map) {
    this.map = map;
    this.estimated = new Track(map, {source: 'estimated', ...TRACK_STYLES.estimated, onCount: showCount});
    this.nav = null;
    this.buoy = null;
    this.keyframes = null;
    this.loads = [];
    this.reloads = 0;       // times a `trajectory` event had the lines read again
    this.legend = null;
  }

  // The lines that grow with the vehicle's `track` events.
  get all() {
    return [this.estimated, this.nav].filter(Boolean);
  }

  // A new status: adds what it says the mission has that is not drawn yet.
  update(status) {
    if (!status) return;
    let added = false;
    const loading = (promise, what) => this.loads.push(promise.catch(error => toast(`${what}: ${error.message}`)));
    if (!this.nav && status.trajectory_corrected) {
      this.nav = new Track(this.map, {source: 'nav', ...TRACK_STYLES.nav});
      this.estimated.line.bringToFront();     // the corrected line on top
      loading(this.nav.load(), 'navigation track');
      added = true;
    }
    if (!this.buoy && status.buoy_fixes > 0) {
      this.buoy = new Track(this.map, {source: 'buoy', ...TRACK_STYLES.buoy});
      this.estimated.line.bringToFront();
      loading(this.buoy.load(), 'buoy track');
      added = true;
    }
    if (!this.keyframes && status.keyframes > 0) {
      this.keyframes = new Keyframes(this.map);
      loading(this.keyframes.load(), 'keyframes');
      added = true;
    }
    if (added) this.showLegend();
  }

  showLegend() {
    this.legend?.remove();
    const vehicle = this.nav ? TRACK_STYLES.estimated : {...TRACK_STYLES.estimated, label: 'vehicle'};
    const entries = [{key: 'estimated', ...vehicle}];
    if (this.nav) entries.push({key: 'nav', ...TRACK_STYLES.nav, toggle: on => this.nav.setVisible(on)});
    if (this.buoy) entries.push({key: 'buoy', ...TRACK_STYLES.buoy, toggle: on => this.buoy.setVisible(on)});
    if (this.keyframes) {
      for (const kind of ['good', 'dropped']) {
        entries.push({key: `keyframes-${kind}`, ...KEYFRAME_STYLES[kind], dot: true,
          toggle: on => this.keyframes.setVisible(kind, on)});
      }
    }
    this.legend = trackLegend(this.map, entries);
  }

  load() {
    return Promise.all([this.estimated.load(), ...this.loads]);
  }

  add(point) {
    for (const track of this.all) track.add(point);
  }

  // The trajectory was corrected (a `trajectory` event): every line read again.
  reload() {
    this.reloads++;
    return Promise.all(this.all.map(track => track.load()));
  }

  catchUp() {
    return Promise.all(this.all.map(track => track.catchUp()));
  }
}
