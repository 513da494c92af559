// The mission's track lines: the estimated one (where the frames were placed)
// always; once the status says the trajectory was corrected, the
// navigation's beside it in another colour, with a legend naming both.

import {$, toast} from './dom.js';
import {Track} from './track.js';
import {trackLegend} from './track_legend.js';

export const TRACK_STYLES = {
  estimated: {label: 'estimated (corrected)', color: '#ffb000'},
  nav: {label: 'navigation (raw)', color: '#3ad1ff', dashArray: '6 5'},
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
    this.navLoaded = null;
    this.legend = null;
  }

  get all() {
    return [this.estimated, this.nav].filter(Boolean);
  }

  // A new status: adds the navigation's track when the trajectory became corrected.
  update(status) {
    if (this.nav || !status || !status.trajectory_corrected) return;
    this.nav = new Track(this.map, {source: 'nav', ...TRACK_STYLES.nav});
    this.estimated.line.bringToFront();     // the corrected line on top
    this.legend = trackLegend(this.map, [
      {key: 'estimated', ...TRACK_STYLES.estimated},
      {key: 'nav', ...TRACK_STYLES.nav, track: this.nav, toggle: true},
    ]);
    this.navLoaded = this.nav.load().catch(error => toast(`navigation track: ${error.message}`));
  }

  load() {
    return Promise.all([this.estimated.load(), this.navLoaded]);
  }

  add(point) {
    for (const track of this.all) track.add(point);
  }

  catchUp() {
    return Promise.all(this.all.map(track => track.catchUp()));
  }
}
