// A tile layer whose tiles are refreshed in place when the server rewrites
// them: URLs carry ?v=VERSION (the tile's ETag) from the versions announced
// by `tile` events, and a rewritten tile on screen gets its new image only
// once that image has loaded, so it never blinks.

const L = window.L;

const key = (z, x, y) => `${z}/${x}/${y}`;

export const LiveTileLayer = L.TileLayer.extend({
  initialize(url, options) {
    L.TileLayer.prototype.initialize.call(this, url, options);
    this._versions = new Map();
    this.refreshed = 0;
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
    return tile;
  },

  // Called for a `tile` event: remember the version, swap the image of the
  // tile if it is on screen.
  refreshTile({z, x, y, version}) {
    const k = key(z, x, y);
    if (this._versions.get(k) === version) return;
    this._versions.set(k, version);
    if (!this._map || z !== this._tileZoom) return;
    const entry = this._tiles[`${x}:${y}:${z}`];
    if (!entry) return;
    const img = entry.el;
    const url = this.getTileUrl(entry.coords);
    if (!entry.loaded) {
      // Still loading its first image: Leaflet's own handlers finish the job.
      img.src = url;
      img.dataset.version = version;
      return;
    }
    const next = new Image();
    next.onload = () => {
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
      this.refreshed++;
      this.fire('tilerefresh', {tile: img, coords: entry.coords, version});
    };
    next.src = url;
  },
});
