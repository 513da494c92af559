// Track and detections as GeoJSON or CSV downloads (fresh from the server).

import {getCollection, getJSON} from './api.js';
import {download, toast} from './dom.js';

const csvField = value => {
  if (value === null || value === undefined) return '';
  const text = String(value);
  return /[",\n\r]/.test(text) ? `"${text.replace(/"/g, '""')}"` : text;
};
const csvLine = fields => fields.map(csvField).join(',');

export function trackCsv(feature) {
  const coords = feature.geometry ? feature.geometry.coordinates : [];
  const times = (feature.properties && feature.properties.times) || [];
  const from = (feature.properties && feature.properties.from) || 0;
  return ['seq,time_s,lat,lon', ...coords.map(([lon, lat], i) => csvLine([from + i, times[i], lat, lon]))].join('\n') + '\n';
}

export function detectionsCsv(collection) {
  // New columns go at the end, so spreadsheets made from older exports still line up.
  const header = 'id,class,score,source,lat,lon,time_s,frame_id,note,created,updated,status,model,size_ew_m,size_ns_m,frames';
  const rows = (collection.features || []).map(f => {
    const p = f.properties;
    const [lon, lat] = f.geometry.coordinates;
    return csvLine([f.id ?? p.id, p.class, p.score, p.source, lat, lon, p.time_s, p.frame_id, p.note, p.created, p.updated,
      p.status, p.model, p.size_m?.[0], p.size_m?.[1], (p.frames || []).join(' ')]);
  });
  return [header, ...rows].join('\n') + '\n';
}

const stem = () => `seamap-${new Date().toISOString().slice(0, 19).replace(/[:T]/g, '-')}`;

export async function exportData(what, format) {
  try {
    if (what === 'track') {
      const feature = await getJSON('/api/track');
      if (format === 'csv') download(`${stem()}-track.csv`, trackCsv(feature), 'text/csv');
      else download(`${stem()}-track.geojson`, JSON.stringify(feature), 'application/geo+json');
    } else {
      const collection = await getCollection('/api/detections');
      if (format === 'csv') download(`${stem()}-detections.csv`, detectionsCsv(collection), 'text/csv');
      else download(`${stem()}-detections.geojson`, JSON.stringify(collection), 'application/geo+json');
    }
  } catch (error) {
    toast(`export failed: ${error.message}`);
  }
}
