// The state of the link to the server, as the operator needs to know it:
// live, slow (tiles take seconds to arrive), silent (no event nor ping for
// a while: maybe down), reconnecting, offline, catching up (a stream that
// came back is replaying what it missed). Also the operator's settings for
// a weak link: low-bandwidth mode and lossless (PNG) tiles, kept in localStorage.

const LOW_KEY = 'seamap.lowBandwidth';
const LOSSLESS_KEY = 'seamap.losslessTiles';
const SILENT_MS = 25000;       // two missed pings (heartbeat_s=10) and some slack
const SLOW_TILE_MS = 3000;     // refreshed tiles (one image at a time) taking this long, median: a slow link
const CATCH_UP_MS = 1500;

class Link {
  constructor() {
    this.lowBandwidth = localStorage.getItem(LOW_KEY) === '1';
    this.lossless = localStorage.getItem(LOSSLESS_KEY) === '1';
    this.modeHandlers = [];
    this.state = 'connecting';
    this.lastHeard = Date.now();
    this.tileMs = [];
    setInterval(() => this.check(), 2000);
  }

  onModeChange(handler) {
    this.modeHandlers.push(handler);
  }

  setLowBandwidth(on) {
    this.lowBandwidth = Boolean(on);
    if (on) localStorage.setItem(LOW_KEY, '1');
    else localStorage.removeItem(LOW_KEY);
    for (const handler of this.modeHandlers) handler();
    this.show();
  }

  setLossless(on) {
    this.lossless = Boolean(on);
    if (on) localStorage.setItem(LOSSLESS_KEY, '1');
    else localStorage.removeItem(LOSSLESS_KEY);
    for (const handler of this.modeHandlers) handler();
  }

  heard() {
    this.lastHeard = Date.now();
    if (this.state === 'silent') this.set('live');
  }

  streamOpen() {
    this.lastHeard = Date.now();
    const wasDown = ['offline', 'reconnecting', 'silent'].includes(this.state);
    this.set(wasDown ? 'catching up' : 'live');
    if (wasDown) setTimeout(() => { if (this.state === 'catching up') this.set('live'); }, CATCH_UP_MS);
  }

  streamReconnecting() {
    this.set('reconnecting');
  }

  streamDown() {
    this.set('offline');
  }

  // How long a refreshed tile's image took (from the tile layer; first loads
  // queue behind each other in the browser and would say nothing of the link).
  tileTime(ms) {
    this.tileMs.push(ms);
    if (this.tileMs.length > 8) this.tileMs.shift();
    this.check();
  }

  get slow() {
    if (this.tileMs.length < 4) return false;
    const sorted = [...this.tileMs].sort((a, b) => a - b);
    return sorted[Math.floor(sorted.length / 2)] > SLOW_TILE_MS;
  }

  check() {
    if (['live', 'slow'].includes(this.state)) {
      if (Date.now() - this.lastHeard > SILENT_MS) this.set('silent');
      else this.set(this.slow ? 'slow' : 'live');
    }
  }

  set(state) {
    if (state === this.state) return;
    this.state = state;
    this.show();
  }

  show() {
    const badge = document.getElementById('connection');
    if (!badge) return;
    const label = {
      live: 'live', slow: 'slow link', silent: 'no news: link down?', reconnecting: 'reconnecting…',
      offline: 'offline', 'catching up': 'catching up…', connecting: 'connecting…',
    }[this.state] || this.state;
    badge.textContent = this.lowBandwidth ? `${label} · low bw` : label;
    badge.dataset.state = this.state;
    badge.title = 'link to the server; click for the link settings';
  }
}

export const link = new Link();
