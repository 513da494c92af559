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

import {link} from './link.js';

const L = window.L;

const key = (z, x, y) => `${z}/${x}/${y}`;
const REFRESH_MS = 3000;       // at most one new image per tile on screen per this
const REFRESH_LOW_MS = 10000;  // in low-bandwidth mode
const SETTLED_MS = 6000;       // a tile without a new version this long is finished

export const LiveTileLayer = L.TileLayer.extend({
  initialize(url, options) {
    L.TileLayer.prototype.initialize.call(this, url, options);
    this._versions = new Map();
    this._changed = new Map();  // key -> time of the last tile event
    this._timers = new Map();   // key -> pending refresh timer
    this._shown = new Map();    // key -> time the last refresh was shown
    this.refreshed = 0;
    this.building = false;
    this._settleTimer = setInterval(() => this._settle(), 1000);
    this._stale = new Set();    // tiles kept off screen (keepBuffer) whose refresh waits until they are seen
  },

  onAdd(map) {
    L.TileLayer.prototype.onAdd.call(this, map);
    map.on('moveend', this._refreshStale, this);
  },

  onRemove(map) {
    map.off('moveend', this._refreshStale, this);
    L.TileLayer.prototype.onRemove.call(this, map);
  },

  // Is the tile on screen (not one Leaflet keeps just outside it)?
  _inView(x, y) {
    const range = this._pxBoundsToTileRange(this._getTiledPixelBounds(this._map.getCenter()));
    return x >= range.min.x && x <= range.max.x && y >= range.min.y && y <= range.max.y;
  },

  _refreshStale() {
    for (const k of [...this._stale]) {
      const [z, x, y] = k.split('/').map(Number);
      if (z !== this._tileZoom || !this._tiles[`${x}:${y}:${z}`]) this._stale.delete(k);
      else if (this._inView(x, y)) {
        this._stale.delete(k);
        this._swap(x, y, z);
      }
    }
  },

  getTileUrl(coords) {
    const url = L.TileLayer.prototype.getTileUrl.call(this, coords);
    const version = this._versions.get(key(this._getZoomForUrl(), coords.x, coords.y));
    return version ? `${url}${url.includes('?') ? '&' : '?'}v=${version}` : url;
  },

  createTile(coords, done) {
    const tile = L.TileLayer.prototype.createTile.call(this, coords, done);
    const z = this._getZoomForUrl();
    tile.dataset.tile = key(z, coords.x, coords.y);
    const version = this._versions.get(tile.dataset.tile);
    if (version) tile.dataset.version = version;
    this._markPending(tile, tile.dataset.tile);
    return tile;
  },

  // The mission's state: once it is no longer building, nothing is pending.
  setBuilding(building) {
    this.building = Boolean(building);
    this._settle();
  },

  _markPending(img, k) {
    const changed = this._changed.get(k);
    const pending = this.building && changed !== undefined && performance.now() - changed < SETTLED_MS;
    if (pending) img.dataset.pending = 'true';
    else delete img.dataset.pending;
  },

  _settle() {
    if (!this._map) return;
    for (const entry of Object.values(this._tiles)) {
      if (entry.el.dataset.pending) this._markPending(entry.el, entry.el.dataset.tile);
    }
  },

  // Called for a `tile` event: remember the version, swap the image of the
  // tile if it is on screen (not sooner than the refresh interval allows).
  refreshTile({z, x, y, version}) {
    const k = key(z, x, y);
    if (this._versions.get(k) === version) return;
    this._versions.set(k, version);
    this._changed.set(k, performance.now());
    if (!this._map || z !== this._tileZoom) return;
    const entry = this._tiles[`${x}:${y}:${z}`];
    if (!entry) return;
    this._markPending(entry.el, k);
    if (this._timers.has(k)) return;  // a refresh is already due: it takes the newest version
    const interval = link.lowBandwidth ? REFRESH_LOW_MS : REFRESH_MS;
    const wait = Math.max(0, (this._shown.get(k) ?? -Infinity) + interval - performance.now());
    this._timers.set(k, setTimeout(() => {
      this._timers.delete(k);
      this._swap(x, y, z);
    }, wait));
  },

  _swap(x, y, z) {
    const k = key(z, x, y);
    const version = this._versions.get(k);
    const entry = this._tiles[`${x}:${y}:${z}`];
    if (!this._map || !entry) return;
    if (!this._inView(x, y)) {  // off screen: fetched when it comes back into view
      this._stale.add(k);
      return;
    }
    const img = entry.el;
    const url = this.getTileUrl(entry.coords);
    this._shown.set(k, performance.now());
    if (!entry.loaded) {
      // Still loading its first image: Leaflet's own handlers finish the job.
      img.src = url;
      img.dataset.version = version;
      return;
    }
    const next = new Image();
    const started = performance.now();
    next.onload = () => {
      link.tileTime(performance.now() - started);
      // Skip when a newer version came meanwhile or the tile left the screen.
      const current = this._tiles[`${x}:${y}:${z}`];
      if (this._versions.get(k) !== version || !current || current.el !== img) return;
      // The tile is already shown: keep Leaflet's load handlers (and their
      // fade-in from transparent) out of the swap.
      img.onload = null;
      img.onerror = null;
      img.src = url;
      img.dataset.version = version;
      img.dataset.refreshed = String(Number(img.dataset.refreshed || 0) + 1);
      this._markPending(img, k);
      this.refreshed++;
      this.fire('tilerefresh', {tile: img, coords: entry.coords, version});
    };
    next.src = url;
  },
});
