// The live event stream (/api/events, Server-Sent Events). Opened before the
// initial state is fetched; events are held until start() so none is lost
// between the fetch and the stream. The stream asks only for what is on
// screen (`scope()`: the tile layer, zoom and area in view), batched by the
// server (longer in low-bandwidth mode); when the view leaves that scope the
// stream is opened again with `after=` the last id seen, so nothing is lost.
// The browser reconnects by itself after a drop and sends Last-Event-ID; the
// server's pings (heartbeat_s) tell a silent link from a dead one.

import {missionUrl} from './api.js';
import {link} from './link.js';

const TYPES = ['tile', 'pose', 'track', 'detection', 'progress', 'trajectory'];
const RETRY_MS = 5000;
const HEARTBEAT_S = 10;

export class LiveEvents {
  constructor(url = '/api/events') {
    this.url = missionUrl(url);
    this.handlers = new Map(TYPES.map(type => [type, []]));
    this.reconnectHandlers = [];
    this.held = [];
    this.started = false;
    this.opened = 0;
    this.lastId = null;
    this.scope = () => ({});      // set by the map once it knows the view
    this.current = null;         // the scope the open stream was asked for
    this.connect();
    link.onModeChange(() => this.reopen());
  }

  query(scope) {
    const params = new URLSearchParams();
    params.set('heartbeat_s', String(HEARTBEAT_S));
    params.set('batch_ms', link.lowBandwidth ? '3000' : '700');
    if (scope.layer !== undefined) params.set('layers', scope.layer);
    if (scope.zoom !== undefined) params.set('zoom', String(scope.zoom));
    if (scope.bbox) params.set('bbox', scope.bbox.map(v => v.toFixed(6)).join(','));
    if (this.lastId !== null) params.set('after', this.lastId);
    return `${this.url}?${params}`;
  }

  connect() {
    this.current = this.scope();
    const source = new EventSource(this.query(this.current));
    this.source = source;
    for (const type of TYPES) source.addEventListener(type, event => this.receive(type, event));
    source.addEventListener('ping', () => link.heard());
    source.addEventListener('open', () => {
      link.streamOpen();
      // After a reconnect, let modules refetch what a lost buffer may miss.
      if (this.opened++ > 0 && !this.reopening) for (const handler of this.reconnectHandlers) handler();
      this.reopening = false;
    });
    source.addEventListener('error', () => {
      if (this.source !== source) return;
      if (source.readyState === EventSource.CLOSED) {
        link.streamDown();
        setTimeout(() => { if (this.source === source) this.connect(); }, RETRY_MS);
      } else {
        link.streamReconnecting();
      }
    });
  }

  // The view moved out of what the stream carries (or the mode changed).
  reopen() {
    if (!this.source) return;
    this.source.close();
    this.reopening = true;
    this.connect();
  }

  // Called by the map on every view change: reopens only when needed.
  viewChanged() {
    const next = this.scope();
    const cur = this.current || {};
    const inside = (a, b) => !a || (b && a[0] >= b[0] && a[1] >= b[1] && a[2] <= b[2] && a[3] <= b[3]);
    if (next.layer === cur.layer && next.zoom === cur.zoom && inside(next.view, cur.bbox)) return;
    this.reopen();
  }

  on(type, handler) {
    this.handlers.get(type).push(handler);
    return this;
  }

  onReconnect(handler) {
    this.reconnectHandlers.push(handler);
    return this;
  }

  receive(type, event) {
    if (event.lastEventId) this.lastId = event.lastEventId;
    link.heard();
    let data;
    try {
      data = JSON.parse(event.data);
    } catch {
      return;
    }
    if (this.started) this.dispatch(type, data);
    else this.held.push([type, data]);
  }

  dispatch(type, data) {
    for (const handler of this.handlers.get(type)) {
      try {
        handler(data);
      } catch (error) {
        console.error(`seamap: ${type} handler`, error);
      }
    }
  }

  start() {
    this.started = true;
    const held = this.held;
    this.held = [];
    for (const [type, data] of held) this.dispatch(type, data);
  }
}
