// Local tangent plane (east/north metres) around the mission origin, on the
// WGS84 ellipsoid: exact enough for a survey a few kilometres across.

const A = 6378137.0;
const E2 = 6.69437999014e-3;
const RAD = Math.PI / 180;

export function localFrame([lat0, lon0]) {
  const s = Math.sin(lat0 * RAD);
  const w = Math.sqrt(1 - E2 * s * s);
  const meridian = A * (1 - E2) / (w * w * w);   // radius of curvature north-south
  const normal = A / w;                          // radius of curvature east-west
  const cos0 = Math.cos(lat0 * RAD);
  return {
    toLocal(lat, lon) {
      return {east: (lon - lon0) * RAD * normal * cos0, north: (lat - lat0) * RAD * meridian};
    },
    toLatLon(east, north) {
      return {lat: lat0 + north / meridian / RAD, lon: lon0 + east / (normal * cos0) / RAD};
    },
  };
}

export function formatMetres(m) {
  if (Math.abs(m) >= 1000) return `${(m / 1000).toFixed(3)} km`;
  if (Math.abs(m) >= 10) return `${m.toFixed(1)} m`;
  return `${m.toFixed(2)} m`;
}

export function formatLatLon(lat, lon) {
  return `${Math.abs(lat).toFixed(7)}°${lat >= 0 ? 'N' : 'S'} ${Math.abs(lon).toFixed(7)}°${lon >= 0 ? 'E' : 'W'}`;
}

export function formatTime(seconds) {
  if (seconds === null || seconds === undefined) return '–';
  const s = Math.max(0, seconds);
  const h = Math.floor(s / 3600), m = Math.floor(s / 60) % 60;
  const sec = (s % 60).toFixed(1).padStart(4, '0');
  return h ? `${h}:${String(m).padStart(2, '0')}:${sec}` : `${m}:${sec}`;
}
