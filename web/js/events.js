// The live event stream (/api/events, Server-Sent Events). Opened before the
// initial state is fetched; events are held until start() so none is lost
// between the fetch and the stream. The browser reconnects by itself and
// sends Last-Event-ID, so the server replays what was missed; a stream the
// server refused (503 when busy) is opened again after a pause.

const TYPES = ['tile', 'pose', 'track', 'detection', 'progress'];
const RETRY_MS = 5000;

export class LiveEvents {
  constructor(url = '/api/events') {
    this.url = url;
    this.handlers = new Map(TYPES.map(type => [type, []]));
    this.reconnectHandlers = [];
    this.held = [];
    this.started = false;
    this.opened = 0;
    this.connect();
  }

  connect() {
    const source = new EventSource(this.url);
    this.source = source;
    for (const type of TYPES) {
      source.addEventListener(type, event => this.receive(type, event));
    }
    source.addEventListener('open', () => {
      setConnection('live');
      // After a reconnect, let modules refetch what a lost buffer may miss.
      if (this.opened++ > 0) for (const handler of this.reconnectHandlers) handler();
    });
    source.addEventListener('error', () => {
      if (source.readyState === EventSource.CLOSED) {
        setConnection('offline');
        setTimeout(() => this.connect(), RETRY_MS);
      } else {
        setConnection('reconnecting');
      }
    });
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

function setConnection(state) {
  const badge = document.getElementById('connection');
  if (badge) {
    badge.textContent = state;
    badge.dataset.state = state;
  }
}
