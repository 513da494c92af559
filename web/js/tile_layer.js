// A tile layer whose tiles are refreshed in place when the server rewrites
// them: URLs carry ?v=VERSION (the tile's ETag) from the versions announced
// by `tile` events, and a rewritten tile on screen gets its new image only
// once that image has loaded, so it never blinks.
//
// On a weak link a tile on screen is fetched again at most every few seconds
// (the newest version then), however often it is repainted. While the map is
// building, a tile that is still being painted is marked pending
// (`data-pending`, drawn faded with a dashed edge) until it has been left
// alone for a while, so a half-painted tile never passes for finished imagery.
//
// Built on Leaflet's public hooks only (createTile, getTileUrl, the layer's
// tileunload/tileabort events, the map's moveend/zoomanim/zoomend and its
// projection), so a Leaflet upgrade cannot break it unseen. The layer's own
// state lives in `this._live`; what runs while it is on a map (the settle
// interval, refresh timers, listeners) starts in onAdd and ends in onRemove.

import {link} from './link.js';

const L = window.L;

const key = (z, x, y) => `${z}/${x}/${y}`;
const REFRESH_MS = 3000;       // at most one new image per tile on screen per this
const REFRESH_LOW_MS = 10000;  // in low-bandwidth mode
const SETTLED_MS = 6000;       // a tile without a new version this long is finished
const SETTLE_EVERY_MS = 1000;  // how often pending tiles are looked at again

export const LiveTileLayer = L.TileLayer.extend({
  initialize(url, options) {
    L.TileLayer.prototype.initialize.call(this, url, options);
    this._live = {
      map: null,             // the map while the layer is on one
      zoomTarget: null,      // the zoom the map is animating to, if it is
      tiles: new Map(),      // key -> {img, coords, state: 'loading' | 'loaded' | 'failed'}: the layer's tiles on the page
      versions: new Map(),   // key -> newest version announced
      changed: new Map(),    // key -> time of the last tile event
      timers: new Map(),     // key -> pending refresh timer
      shown: new Map(),      // key -> time the last refresh was shown
      stale: new Set(),      // tiles kept off screen (keepBuffer) whose refresh waits until they are seen
      settleTimer: null,
    };
    this.refreshed = 0;
    this.building = false;
  },

  onAdd(map) {
    const live = this._live;
    live.map = map;
    this.on('tileunload tileabort', forgetTile, this);
    map.on(MAP_EVENTS, this);
    live.settleTimer = setInterval(() => settle(this), SETTLE_EVERY_MS);
    L.TileLayer.prototype.onAdd.call(this, map);
  },

  onRemove(map) {
    L.TileLayer.prototype.onRemove.call(this, map);  // unloads every tile
    const live = this._live;
    map.off(MAP_EVENTS, this);
    this.off('tileunload tileabort', forgetTile, this);
    clearInterval(live.settleTimer);
    for (const timer of live.timers.values()) clearTimeout(timer);
    live.timers.clear();
    live.stale.clear();
    live.tiles.clear();
    live.settleTimer = null;
    live.zoomTarget = null;
    live.map = null;
  },

  // The zoom the layer fetches its tiles at for the map's view (or the view
  // the map is zooming to): Leaflet's rule, the zoom rounded, then held
  // within the native zooms. Undefined while the layer is on no map.
  tileZoom() {
    const {map, zoomTarget} = this._live;
    if (!map) return undefined;
    const zoom = Math.round(zoomTarget ?? map.getZoom());
    const {minNativeZoom, maxNativeZoom} = this.options;
    if (minNativeZoom !== undefined && zoom < minNativeZoom) return minNativeZoom;
    if (maxNativeZoom !== undefined && zoom > maxNativeZoom) return maxNativeZoom;
    return zoom;
  },

  getTileUrl(coords) {
    const url = L.TileLayer.prototype.getTileUrl.call(this, coords);
    const version = this._live.versions.get(key(urlZoom(this, coords), coords.x, coords.y));
    return version ? `${url}${url.includes('?') ? '&' : '?'}v=${version}` : url;
  },

  createTile(coords, done) {
    const k = key(urlZoom(this, coords), coords.x, coords.y);
    const entry = {img: null, coords, state: 'loading'};
    // Leaflet's handlers report every load of the image. Only its first
    // load, or the first good one after a failure (a tile not painted yet,
    // 204), may reach Leaflet: each report fades the tile in from
    // transparent, which a swap of a tile already shown must not do.
    entry.img = L.TileLayer.prototype.createTile.call(this, coords, (error, tile) => {
      if (entry.state === 'loaded') return;
      entry.state = error ? 'failed' : 'loaded';
      done(error, tile);
    });
    const img = entry.img;
    img.dataset.tile = k;
    const version = this._live.versions.get(k);
    if (version) img.dataset.version = version;
    markPending(this, img, k);
    this._live.tiles.set(k, entry);
    return img;
  },

  // The mission's state: once it is no longer building, nothing is pending.
  setBuilding(building) {
    this.building = Boolean(building);
    settle(this);
  },

  // Called for a `tile` event: remember the version, swap the image of the
  // tile if it is on screen (not sooner than the refresh interval allows).
  refreshTile({z, x, y, version}) {
    const live = this._live;
    const k = key(z, x, y);
    if (live.versions.get(k) === version) return;
    live.versions.set(k, version);
    live.changed.set(k, performance.now());
    const entry = live.tiles.get(k);
    if (!live.map || !entry || entry.coords.z !== this.tileZoom()) return;
    markPending(this, entry.img, k);
    if (live.timers.has(k)) return;  // a refresh is already due: it takes the newest version
    const interval = link.lowBandwidth ? REFRESH_LOW_MS : REFRESH_MS;
    const wait = Math.max(0, (live.shown.get(k) ?? -Infinity) + interval - performance.now());
    live.timers.set(k, setTimeout(() => {
      live.timers.delete(k);
      swap(this, k);
    }, wait));
  },
});

// The map's events the layer follows while on it (context: the layer).
const MAP_EVENTS = {
  moveend: refreshStale,
  zoomanim(event) {
    if (!event.noUpdate) this._live.zoomTarget = event.zoom;  // a pinch leaves Leaflet's tile zoom as it is
  },
  zoomend() {
    this._live.zoomTarget = null;
  },
};

// The z of a tile's URL (and of its `tile` events) for Leaflet's coords.
function urlZoom(layer, coords) {
  const {zoomReverse, maxZoom, zoomOffset} = layer.options;
  return (zoomReverse ? maxZoom - coords.z : coords.z) + zoomOffset;
}

// A tile left the page (tileunload, tileabort; context: the layer).
function forgetTile(event) {
  const tiles = this._live.tiles;
  const k = event.tile.dataset.tile;
  if (tiles.get(k)?.img === event.tile) tiles.delete(k);
}

// Is the tile on screen, not one Leaflet keeps just outside it? Leaflet's
// tile range for the view, from the map's public projection.
function onScreen(layer, coords) {
  const {map, zoomTarget} = layer._live;
  const mapZoom = zoomTarget === null ? map.getZoom() : Math.max(zoomTarget, map.getZoom());
  const centre = map.project(map.getCenter(), coords.z).floor();
  const half = map.getSize().divideBy(map.getZoomScale(mapZoom, coords.z) * 2);
  const size = layer.getTileSize();
  const min = centre.subtract(half).unscaleBy(size).floor();
  const max = centre.add(half).unscaleBy(size).ceil().subtract([1, 1]);
  return coords.x >= min.x && coords.x <= max.x && coords.y >= min.y && coords.y <= max.y;
}

// The map stopped moving: refresh the stale tiles now on screen (context: the layer).
function refreshStale() {
  const live = this._live;
  for (const k of [...live.stale]) {
    const entry = live.tiles.get(k);
    if (!entry || entry.coords.z !== this.tileZoom()) live.stale.delete(k);
    else if (onScreen(this, entry.coords)) {
      live.stale.delete(k);
      swap(this, k);
    }
  }
}

function markPending(layer, img, k) {
  const changed = layer._live.changed.get(k);
  const pending = layer.building && changed !== undefined && performance.now() - changed < SETTLED_MS;
  if (pending) img.dataset.pending = 'true';
  else delete img.dataset.pending;
}

function settle(layer) {
  if (!layer._live.map) return;
  for (const {img} of layer._live.tiles.values()) {
    if (img.dataset.pending) markPending(layer, img, img.dataset.tile);
  }
}

// Shows the newest version of a tile: at once while it still loads its first
// image, else once the new image has loaded (no blink).
function swap(layer, k) {
  const live = layer._live;
  const entry = live.tiles.get(k);
  if (!live.map || !entry) return;
  if (!onScreen(layer, entry.coords)) {  // off screen: fetched when it comes back into view
    live.stale.add(k);
    return;
  }
  const {img, coords} = entry;
  const version = live.versions.get(k);
  const url = layer.getTileUrl(coords);
  live.shown.set(k, performance.now());
  if (entry.state === 'loading') {
    // Still loading its first image: Leaflet's own handlers finish the job.
    img.src = url;
    img.dataset.version = version;
    return;
  }
  const next = new Image();
  const started = performance.now();
  next.onload = () => {
    link.tileTime(performance.now() - started);
    // Skip when a newer version came meanwhile or the tile left the page.
    if (live.versions.get(k) !== version || live.tiles.get(k) !== entry) return;
    img.src = url;  // reaches Leaflet only if the tile had failed (createTile)
    img.dataset.version = version;
    img.dataset.refreshed = String(Number(img.dataset.refreshed || 0) + 1);
    markPending(layer, img, k);
    layer.refreshed++;
    layer.fire('tilerefresh', {tile: img, coords, version});
  };
  next.src = url;
}
