// Console start-up: wires the map, the live stream and the panel together.

import {checkToken, getJSON, getToken, setToken} from './api.js';
import {$, toast} from './dom.js';
import {LiveEvents} from './events.js';
import {exportData} from './export.js';
import {localFrame} from './geo.js';
import {Detections} from './detections.js';
import {Measure} from './measure.js';
import {Photos} from './photos.js';
import {Vehicle, showStatus} from './live.js';
import {Tracks} from './tracks.js';
import {addPhotoLayers, createMap, cursorReadout, initialView} from './map.js';

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
  if (photoLayers) initialView(map, photoLayers.tilejson, status);
  else {
    toast(`no map yet: ${tilesResult.reason.message}`);
    initialView(map, {}, status);
  }

  const origin = status && Array.isArray(status.origin) ? status.origin : null;
  cursorReadout(map, $('#cursor'), origin);
  const frame = origin ? localFrame(origin) : null;

  const vehicle = new Vehicle(map);
  const tracks = new Tracks(map);              // the navigation's too when corrected
  tracks.update(status);
  const detections = new Detections(map, {canEdit, frame});
  const photos = new Photos(map);
  const measure = new Measure(map);
  if (status) vehicle.update(status.last_pose);

  await Promise.allSettled([
    tracks.load().catch(error => toast(`track: ${error.message}`)),
    detections.load().catch(error => toast(`detections: ${error.message}`)),
  ]);

  const tileLayerFor = name => photoLayers && (photoLayers.layers.get(name) || photoLayers.main);
  let retryingTiles = false;
  live
    .on('tile', event => tileLayerFor(event.layer)?.refreshTile(event))
    .on('pose', pose => vehicle.update(pose))
    .on('track', point => tracks.add(point))
    .on('detection', event => detections.onEvent(event))
    .on('progress', next => {
      // Progress events may leave out what only /api/status adds (token_required, writable).
      status = {...status, ...next};
      showStatus(status);
      tracks.update(status);
      if (!photoLayers && !retryingTiles) {        // the map had no tiles at start
        retryingTiles = true;
        addPhotoLayers(map).then(result => {
          photoLayers = result;
          initialView(map, result.tilejson, status);
        }).catch(() => {}).finally(() => { retryingTiles = false; });
      }
    })
    .onReconnect(async () => {
      try {
        status = await getJSON('/api/status');
        showStatus(status);
        showEditing();
        tracks.update(status);
      } catch { /* the stream will tell */ }
      tracks.catchUp();
      detections.load().catch(() => {});
    });
  live.start();

  map.on('click', event => {
    const mode = document.body.dataset.mode;
    if (mode === 'measure') measure.click(event.latlng);
    else if (mode === 'mark' && canEdit()) detections.addAt(event.latlng);
    else photos.at(event.latlng);
  });

  for (const radio of document.querySelectorAll('input[name="mode"]')) {
    radio.addEventListener('change', () => {
      setMode(radio.value);
      if (radio.value === 'measure') measure.clear();
    });
  }
  $('#follow').addEventListener('change', event => {
    vehicle.follow = event.target.checked;
    if (vehicle.follow && vehicle.marker.getLatLng()) map.panTo(vehicle.marker.getLatLng());
  });
  map.on('dragstart', () => {
    if (vehicle.follow) {
      vehicle.follow = false;
      $('#follow').checked = false;
    }
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
  window.seamap = {map, live, track: tracks.estimated, tracks, detections, photos, measure, vehicle,
    get layers() { return photoLayers; }, get status() { return status; }};
  document.body.dataset.ready = 'true';
}

start().catch(error => {
  console.error(error);
  toast(`console failed to start: ${error.message}`);
});
