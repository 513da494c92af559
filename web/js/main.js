// Console start-up: wires the map, the live stream and the panel together.

import {checkToken, getJSON, getToken, missionBase, setToken} from './api.js';
import {$, toast} from './dom.js';

const L = window.L;
import {LiveEvents} from './events.js';
import {exportData} from './export.js';
import {Footprints} from './footprints.js';
import {localFrame} from './geo.js';
import {Detections} from './detections.js';
import {Measure} from './measure.js';
import {Photos} from './photos.js';
import {Relief} from './relief.js';
import {link} from './link.js';
import {Vehicle, showStatus} from './live.js';
import {Swipe} from './swipe.js';
import {Tracks} from './tracks.js';
import {addPhotoLayers, createMap, cursorReadout, initialView, viewScope} from './map.js';
import {readViewState, writeViewState} from './url_state.js';
import {fillHelp, keyboardShortcuts, showFollowing, toggleHelp, viewControls} from './view_controls.js';

let status = null;
let tokenRefused = false;  // the last token entered (or saved) was wrong
const canEdit = () => Boolean(status) && status.writable !== false && (!status.token_required || Boolean(getToken()));

function showEditing() {
  document.body.classList.toggle('can-edit', canEdit());
  const state = $('#token-state');
  if (!status) return;
  if (status.writable === false) state.textContent = 'this mission is read only';
  else if (!status.token_required) state.textContent = 'this server needs no token to edit marks';
  else if (tokenRefused) state.textContent = 'wrong token: the server refused it; marks stay read only';
  else state.textContent = getToken() ? 'token set: marks can be edited' : 'read only: set the token to edit marks';
  state.classList.toggle('refused', tokenRefused);
  if (!canEdit() && $('#mode-mark').checked) setMode('photos');
}

// Keeps `token` if the server takes it (checked at once, before any write);
// a wrong one is dropped and said so. False when it was refused.
async function acceptToken(token, entered) {
  let right = true;
  if (token && status && status.token_required) {
    try {
      right = await checkToken(token);
    } catch (error) {
      toast(`the token could not be checked (${error.message}); kept`);
    }
  }
  tokenRefused = !right;
  setToken(right ? token : '');
  showEditing();
  if (!right) toast(entered ? 'wrong token: the server refused it' : 'the saved token is wrong: enter it again');
  return right;
}

function setMode(mode) {
  document.body.dataset.mode = mode;
  const radio = document.querySelector(`input[name="mode"][value="${mode}"]`);
  if (radio) radio.checked = true;
}

async function start() {
  const map = createMap($('#map'));
  const live = new LiveEvents();                 // opened first, events held
  const [statusResult, tilesResult] = await Promise.allSettled([getJSON('/api/status'), addPhotoLayers(map)]);
  if (statusResult.status === 'fulfilled') status = statusResult.value;
  else toast(`status: ${statusResult.reason.message}`);
  showStatus(status);
  showEditing();
  if (getToken()) acceptToken(getToken(), false);  // a saved token may be out of date

  let photoLayers = tilesResult.status === 'fulfilled' ? tilesResult.value : null;
  const wanted = readViewState();
  const chooseLayer = name => {
    const layer = name && photoLayers && photoLayers.distinct.get(name);
    if (!layer || layer === photoLayers.active) return;
    map.removeLayer(photoLayers.active);
    layer.addTo(map);
    photoLayers.active = layer;
  };
  const firstView = () => {
    if (wanted.center) map.setView(wanted.center, wanted.zoom);
    else initialView(map, photoLayers ? photoLayers.tilejson : {}, status);
  };
  if (photoLayers) chooseLayer(wanted.layer);
  else toast(`no map yet: ${tilesResult.reason.message}`);
  firstView();

  // Swipe to compare raw and enhanced; the stream then carries both layers' tiles.
  const swipe = new Swipe(map, () => photoLayers, () => {
    if (photoLayers) photoLayers.compare = swipe.compare;
    swipe.compare?.setBuilding(status?.state === 'building');
    live.viewChanged();
  });
  swipe.bindCheckbox();


  // The height model's relief over the photos, with its legend (a mission built with --terrain).
  const relief = new Relief(map, photoLayers ? photoLayers.tilejson : null);
  relief.bindCheckbox($('#relief'), $('#relief-row'));

  const origin = status && Array.isArray(status.origin) ? status.origin : null;
  cursorReadout(map, $('#cursor'), origin);
  const frame = origin ? localFrame(origin) : null;

  const vehicle = new Vehicle(map);
  const tracks = new Tracks(map);              // the navigation's too when corrected
  tracks.update(status);
  const photos = new Photos(map);
  const detections = new Detections(map, {canEdit, frame, openPhotos: (ids, start) => photos.openList(ids, start)});
  detections.enableBoxDrawing(() => document.body.dataset.mode === 'mark');
  if (status) detections.setMissionClasses(status.classes);
  const measure = new Measure(map);
  const footprints = new Footprints(map, id => photos.openId(id));
  if (status) vehicle.update(status.last_pose);

  await Promise.allSettled([
    tracks.load().catch(error => toast(`track: ${error.message}`)),
    detections.load().catch(error => toast(`detections: ${error.message}`)),
  ]);

  const tileLayerFor = name => photoLayers && (photoLayers.layers.get(name) || photoLayers.main);
  const setBuilding = () => {
    footprints.building = status?.state === 'building';
    for (const layer of new Set(photoLayers ? photoLayers.layers.values() : [])) layer.setBuilding(status?.state === 'building');
    swipe.compare?.setBuilding(status?.state === 'building');
  };
  setBuilding();
  // The stream carries only the tiles of the view: reopened when the view leaves what it asked for.
  live.scope = () => viewScope(map, photoLayers);
  if (live.lastId === null && status && status.event_seq !== undefined) live.lastId = String(status.event_seq);
  live.reopen();
  let retryingTiles = false;
  live
    .on('tile', event => {
      tileLayerFor(event.layer)?.refreshTile(event);
      if (swipe.compare && swipe.compare.eventLayer === (event.layer || '')) swipe.compare.refreshTile(event);
    })
    .on('pose', pose => vehicle.update(pose))
    .on('track', point => tracks.add(point))
    .on('detection', event => detections.onEvent(event))
    .on('progress', next => {
      // Progress events may leave out what only /api/status adds (token_required, writable).
      status = {...status, ...next};
      showStatus(status);
      tracks.update(status);
      setBuilding();
      if (!photoLayers && !retryingTiles) {        // the map had no tiles at start
        retryingTiles = true;
        addPhotoLayers(map).then(result => {
          photoLayers = result;
          swipe.showCheckbox();
          setBuilding();
          if (!wanted.center) initialView(map, result.tilejson, status);
          live.reopen();
        }).catch(() => {}).finally(() => { retryingTiles = false; });
      }
    })
    .onReconnect(async () => {
      try {
        status = await getJSON('/api/status');
        showStatus(status);
        showEditing();
        detections.setMissionClasses(status.classes);
        tracks.update(status);
      } catch { /* the stream will tell */ }
      tracks.catchUp();
      detections.load().catch(() => {});
    });
  live.start();

  map.on('click', event => {
    const mode = document.body.dataset.mode;
    if (mode === 'measure') measure.click(event.latlng);
    else if (mode === 'mark' && canEdit()) { if (!detections.justDrew()) detections.addAt(event.latlng); }
    else {
      photos.at(event.latlng);
      if (relief.on) relief.at(event.latlng);
    }
  });

  for (const radio of document.querySelectorAll('input[name="mode"]')) {
    radio.addEventListener('change', () => {
      setMode(radio.value);
      if (radio.value === 'measure') measure.clear();
      if (document.body.classList.contains('panel-open') && matchMedia('(max-width: 720px)').matches) {
        document.body.classList.remove('panel-open');   // on a phone: back to the map to click it
      }
    });
  }
  const hasVehicle = () => map.hasLayer(vehicle.marker);
  const setFollow = on => {
    vehicle.follow = Boolean(on);
    showFollowing(vehicle.follow);
    if (vehicle.follow && hasVehicle()) map.panTo(vehicle.marker.getLatLng(), {animate: false});
    saveView();
  };
  $('#follow').addEventListener('change', event => setFollow(event.target.checked));
  map.on('dragstart', () => { if (vehicle.follow) setFollow(false); });

  // Fit the mission: the track and the map's bounds together.
  const fitMission = () => {
    let bounds = L.latLngBounds(tracks.estimated.points);
    const b = photoLayers?.tilejson?.bounds;
    if (Array.isArray(b) && b.length === 4 && b[2] > b[0]) bounds = bounds.extend([[b[1], b[0]], [b[3], b[2]]]);
    if (hasVehicle()) bounds.extend(vehicle.marker.getLatLng());
    if (!bounds.isValid()) return;
    setFollow(false);
    map.fitBounds(bounds, {padding: [20, 20], maxZoom: photoLayers ? photoLayers.main.options.maxNativeZoom : 20});
  };
  const toVehicle = () => {
    if (!hasVehicle()) return toast('no vehicle position yet');
    map.setView(vehicle.marker.getLatLng(), Math.max(map.getZoom(), map.getMaxZoom() - 4), {animate: false});
  };
  const fullscreen = () => {
    if (document.fullscreenElement) document.exitFullscreen?.();
    else document.documentElement.requestFullscreen?.().catch(() => toast('fullscreen is not allowed here'));
  };
  viewControls(map, {fit: fitMission, vehicle: toVehicle, toggleFollow: () => setFollow(!vehicle.follow),
    fullscreen, help: () => toggleHelp()});
  fillHelp();
  $('#help-close').addEventListener('click', () => toggleHelp(false));

  // Coordinates to the clipboard: key c (under the pointer) or a long press / right click.
  let pointer = null;
  map.on('mousemove', event => { pointer = event.latlng; });
  map.on('mouseout', () => { pointer = null; });
  const copyAt = latlng => {
    if (!latlng) return toast('point at the map first');
    const text = `${latlng.lat.toFixed(7)}, ${latlng.lng.toFixed(7)}`;
    navigator.clipboard?.writeText(text).then(() => toast(`copied ${text}`), () => toast(text));
    if (!navigator.clipboard) toast(text);
  };
  map.on('contextmenu', event => copyAt(event.latlng));

  // The view in the URL, and the event stream following the view.
  function saveView() {
    writeViewState({center: map.getCenter(), zoom: map.getZoom(),
      layer: photoLayers && photoLayers.active !== photoLayers.main ? photoLayers.nameOf(photoLayers.active) : null,
      follow: vehicle.follow});
  }
  let viewTimer = null;
  map.on('moveend zoomend baselayerchange', () => {
    clearTimeout(viewTimer);
    viewTimer = setTimeout(() => { saveView(); live.viewChanged(); }, 300);
  });
  if (wanted.follow) setFollow(true);

  // Layer opacity, low-bandwidth mode, lossless tiles.
  $('#layer-opacity').addEventListener('input', event => {
    for (const layer of new Set(photoLayers ? photoLayers.layers.values() : [])) layer.setOpacity(Number(event.target.value));
    swipe.compare?.setOpacity(Number(event.target.value));
  });
  const lowBox = $('#low-bandwidth');
  lowBox.checked = link.lowBandwidth;
  lowBox.addEventListener('change', () => link.setLowBandwidth(lowBox.checked));
  const losslessBox = $('#lossless-tiles');
  losslessBox.checked = link.lossless;
  losslessBox.addEventListener('change', () => link.setLossless(losslessBox.checked));
  $('#connection').addEventListener('click', () => {
    document.body.classList.add('panel-open');
    $('#view').scrollIntoView({block: 'start'});
  });
  link.show();

  keyboardShortcuts({
    f: fitMission, v: toVehicle, l: () => setFollow(!vehicle.follow), u: fullscreen, '?': () => toggleHelp(),
    c: () => copyAt(pointer), b: () => { link.setLowBandwidth(!link.lowBandwidth); lowBox.checked = link.lowBandwidth; },
    p: () => setMode('photos'), m: () => { setMode('measure'); measure.clear(); },
    a: () => { if (canEdit()) setMode('mark'); },
    Escape: () => { toggleHelp(false); map.closePopup(); },
  });

  $('#token').value = getToken();
  $('#token-form').addEventListener('submit', async event => {
    event.preventDefault();
    const accepted = await acceptToken($('#token').value.trim(), true);
    for (const feature of [...detections.features.values()]) detections.upsert(feature, false);
    detections.render();
    if (accepted) toast(getToken() ? 'token set' : 'token cleared');
  });

  for (const button of document.querySelectorAll('[data-export]')) {
    button.addEventListener('click', () => exportData(button.dataset.export, button.dataset.format));
  }

  const toggle = $('#panel-toggle');
  toggle.addEventListener('click', () => {
    const open = document.body.classList.toggle('panel-open');
    toggle.setAttribute('aria-expanded', String(open));
  });

  // For debugging from the browser console and for the end-to-end test.
  window.seamap = {map, live, link, track: tracks.estimated, tracks, detections, photos, measure, footprints, vehicle, swipe, relief, fitMission, toVehicle, setFollow,
    get layers() { return photoLayers; }, get status() { return status; }};
  // A mission of a catalogue (`seamap serve FOLDER`): a way back to the others.
  document.getElementById('catalogue-link').hidden = !missionBase;
  document.body.dataset.ready = 'true';
}

start().catch(error => {
  console.error(error);
  toast(`console failed to start: ${error.message}`);
});
