// The Leaflet map: photo tile layers from TileJSON (with a layer switch when
// the mission has more than one), scale bar and the cursor readout.

import {getJSON, missionUrl} from './api.js';
import {escapeHtml} from './dom.js';
import {formatLatLon, formatMetres, localFrame} from './geo.js';
import {link} from './link.js';
import {LiveTileLayer} from './tile_layer.js';

const L = window.L;
const OVERZOOM = 3;

export function createMap(element) {
  const map = L.map(element, {
    zoomControl: true,
    attributionControl: true,
    preferCanvas: false,
    minZoom: 0,
    maxZoom: 22,
  });
  L.control.scale({metric: true, imperial: false, maxWidth: 160}).addTo(map);
  return map;
}

function layerNames(tilejson) {
  const layers = tilejson.seamap_layers;
  if (Array.isArray(layers)) return layers;
  if (typeof layers === 'string' && layers) return layers.split(',').map(s => s.trim()).filter(Boolean);
  return [];
}

// The tile URL in the format for the link: WebP where the server offers it
// for a PNG map (a fifth of the bytes), unless the operator wants lossless.
export function tileUrl(tilejson) {
  const url = tilejson.tiles[0];
  const formats = Array.isArray(tilejson.seamap_formats) ? tilejson.seamap_formats : [];
  if (link.lossless || !formats.includes('webp') || formats[0] === 'webp') return url;
  return url.replace(/\.(png|jpg|jpeg)(\?|$)/, '.webp$2');
}

// A second instance of a photo layer (for the swipe), unknown to the layer
// switch, which would take its adding for a change of the layer shown.
export function twinLayer(layer) {
  const twin = tileLayerFrom(layer.tilejson);
  twin.eventLayer = layer.eventLayer;
  return twin;
}

function tileLayerFrom(tilejson) {
  const maxzoom = tilejson.maxzoom ?? 22;
  const minzoom = tilejson.minzoom ?? 0;
  const layer = new LiveTileLayer(tileUrl(tilejson), {
    maxNativeZoom: maxzoom,
    maxZoom: maxzoom + OVERZOOM,
    minNativeZoom: minzoom,
    minZoom: Math.max(0, minzoom - 2),
    tileSize: tilejson.seamap_tile_size ? Number(tilejson.seamap_tile_size) : 256,
    // Leaflet writes attributions as HTML: the map's text is escaped, shown as typed.
    attribution: escapeHtml(tilejson.attribution || 'SeaMap'),
    keepBuffer: 2,
    updateWhenZooming: false,
  });
  layer.tilejson = tilejson;
  return layer;
}

// Loads /tiles.json (and /tiles/{layer}.json for extra layers), adds the
// first layer, and answers {layers: Map(name -> layer), main, tilejson}.
export async function addPhotoLayers(map) {
  const tilejson = await getJSON('/tiles.json');
  const main = tileLayerFrom(tilejson);
  const names = layerNames(tilejson);
  const layers = new Map();
  const mainName = names[0] || 'map';
  main.eventLayer = '';       // tile events name the main map ""
  layers.set(mainName, main);
  for (const name of names.slice(1)) {
    try {
      const extra = await getJSON(`/tiles/${encodeURIComponent(name)}.json`);
      if (extra.tiles && extra.tiles[0] !== tilejson.tiles[0]) layers.set(name, tileLayerFrom(extra));
      else layers.set(name, main);
    } catch {
      layers.set(name, tileLayerFrom({...tilejson, tiles: [missionUrl(`/tiles/${encodeURIComponent(name)}/{z}/{x}/{y}.${tilejson.format || 'png'}`)]}));
    }
    if (layers.get(name) !== main) layers.get(name).eventLayer = name;
  }
  main.addTo(map);
  map.setMaxZoom(main.options.maxZoom);
  map.setMinZoom(main.options.minZoom);
  const distinct = new Map([...layers].filter(([name, layer]) => name === mainName || layer !== main));
  if (distinct.size > 1) {
    // The layer control writes names as HTML: a map's layer names are escaped.
    const named = [...distinct].map(([name, layer]) => [escapeHtml(name), layer]);
    L.control.layers(Object.fromEntries(named), null, {collapsed: true, position: 'topright'}).addTo(map);
  }
  const result = {layers, main, tilejson, active: main, distinct,
    nameOf: layer => [...distinct].find(([, l]) => l === layer)?.[0] || mainName};
  map.on('baselayerchange', event => { result.active = event.layer; });
  // The operator switched lossless tiles on or off: reload in the other format.
  link.onModeChange(() => {
    for (const layer of new Set(layers.values())) layer.setUrl(tileUrl(layer.tilejson));  // redraws only a changed URL
  });
  return result;
}

// What the live stream should carry for this view: tile events of the layer
// shown, at the zoom its tiles are fetched at, around the view (half a
// screen of margin, so small pans need no new stream).
export function viewScope(map, photoLayers) {
  if (!photoLayers || !map._loaded) return {};
  const layer = photoLayers.active;
  // Comparing by swipe: the other layer's tiles are on screen too.
  const shown = [layer, ...(photoLayers.compare ? [photoLayers.compare] : [])];
  const zoom = layer.tileZoom() ?? Math.round(Math.max(layer.options.minNativeZoom ?? 0,
    Math.min(layer.options.maxNativeZoom ?? 22, map.getZoom())));
  const b = map.getBounds();
  const view = [b.getWest(), b.getSouth(), b.getEast(), b.getNorth()];
  const padded = b.pad(0.5);
  const clamp = (v, lo, hi) => Math.max(lo, Math.min(hi, v));
  const bbox = [clamp(padded.getWest(), -180, 180), clamp(padded.getSouth(), -85.06, 85.06),
    clamp(padded.getEast(), -180, 180), clamp(padded.getNorth(), -85.06, 85.06)];
  return {layer: shown.map(l => l.eventLayer ?? '').join(','), zoom, view, bbox};
}

// The first view: the map's bounds, else its centre, else the vehicle.
export function initialView(map, tilejson, status) {
  const b = tilejson.bounds;
  const maxzoom = tilejson.maxzoom ?? 20;
  if (Array.isArray(b) && b.length === 4 && b[2] > b[0] && b[3] > b[1]) {
    map.fitBounds([[b[1], b[0]], [b[3], b[2]]], {maxZoom: maxzoom, padding: [10, 10]});
    return;
  }
  const pose = status && status.last_pose;
  if (pose) map.setView([pose.lat, pose.lon], maxzoom - 1);
  else if (Array.isArray(tilejson.center)) map.setView([tilejson.center[1], tilejson.center[0]], Math.min(tilejson.center[2] ?? maxzoom - 2, maxzoom));
  else if (status && status.origin) map.setView(status.origin, maxzoom - 2);
  else map.setView([0, 0], 2);
}

// Cursor position in lat/lon and east/north metres from the mission origin.
export function cursorReadout(map, element, origin) {
  const frame = origin ? localFrame(origin) : null;
  const show = latlng => {
    let text = formatLatLon(latlng.lat, latlng.lng);
    if (frame) {
      const {east, north} = frame.toLocal(latlng.lat, latlng.lng);
      text += ` · E ${formatMetres(east)} N ${formatMetres(north)}`;
    }
    element.textContent = text;
  };
  map.on('mousemove', event => show(event.latlng));
  map.on('click', event => show(event.latlng));
  // A readout of where the pointer was is wrong once it has left the map.
  map.on('mouseout', () => { element.textContent = ''; });
  map.getContainer().addEventListener('mouseleave', () => { element.textContent = ''; });
}
