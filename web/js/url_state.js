// The view in the URL (#z=ZOOM&c=LAT,LON&layer=NAME&follow=1), so a reload or
// a shared link opens the same place, layer and follow state. Written with
// replaceState (no history entry per pan).

export function readViewState(hash = location.hash) {
  const params = new URLSearchParams(hash.replace(/^#/, ''));
  const zoom = Number(params.get('z'));
  const [lat, lon] = (params.get('c') || '').split(',').map(Number);
  const state = {layer: params.get('layer') || null, follow: params.get('follow') === '1'};
  if (params.has('z') && Number.isFinite(zoom) && Number.isFinite(lat) && Number.isFinite(lon) &&
      Math.abs(lat) <= 90 && Math.abs(lon) <= 180) {
    state.center = [lat, lon];
    state.zoom = zoom;
  }
  return state;
}

export function writeViewState({center, zoom, layer, follow}) {
  const params = new URLSearchParams();
  params.set('z', String(Math.round(zoom * 100) / 100));
  params.set('c', `${center.lat.toFixed(7)},${center.lng.toFixed(7)}`);
  if (layer) params.set('layer', layer);
  if (follow) params.set('follow', '1');
  const hash = `#${params.toString().replace(/%2C/g, ',')}`;
  if (hash !== location.hash) history.replaceState(null, '', hash);
}
