// End-to-end test of the operator console: a real `seamap replay` serves a
// simulated survey while headless Chromium watches the console build it; then
// `seamap serve` follows a mission with a corrected trajectory
// (corrected_tracks.mjs).
//
//   node tests/e2e/console.e2e.mjs
//
// Environment: SEAMAP_BIN (seamap binary, default build/seamap),
// SEAMAP_CORRECTED_MISSION (the test tool, default build/corrected_mission),
// SEAMAP_SOURCE_DIR (repo root, default two folders up), SEAMAP_ARTIFACTS
// (screenshots, default a temp folder), SEAMAP_E2E_SPEED (replay speed,
// default 0.75), SEAMAP_E2E_URL + SEAMAP_E2E_TOKEN (test a server that is
// already running instead of starting one).

import fs from 'node:fs';
import http from 'node:http';
import path from 'node:path';
import {checkConsoleTools} from './console_tools.mjs';
import {checkCorrectedTracks} from './corrected_tracks.mjs';
import {runE2E, freePort, run, sleep, waitFor, waitForOutput, watchIntervals} from './harness.mjs';

const speed = process.env.SEAMAP_E2E_SPEED || '0.75';
const FRAMES = 200;   // about 50 s of replay, so the early checks watch it grow
const TOTAL_TIMEOUT_MS = 200000;   // a hung browser or server never hangs ctest (TIMEOUT 300)
const URL_GIVEN = Boolean(process.env.SEAMAP_E2E_URL);   // a server already running: nothing started

async function startServer({seamap, sourceDir, work, start}) {
  if (URL_GIVEN) {
    return {base: process.env.SEAMAP_E2E_URL.replace(/\/?$/, '/'), token: process.env.SEAMAP_E2E_TOKEN || ''};
  }
  const survey = path.join(work, 'survey');
  await run(seamap, ['simulate', '--out', survey, '--frames', String(FRAMES), '--quiet']);
  const port = await freePort();
  const token = `e2e-${process.pid}-${Date.now()}`;
  fs.mkdirSync(path.join(work, 'out'));
  const server = start(seamap, ['replay', survey, '--speed', speed,
    '--out', path.join(work, 'out', 'mission.mbtiles'), '--port', String(port),
    '--web', path.join(sourceDir, 'web'), '--token', token]);  // serves on after the replay: the runner stops it
  await waitForOutput(server, new RegExp(`serving http://127\\.0\\.0\\.1:${port}/`), 20000);
  return {base: `http://127.0.0.1:${port}/`, token};
}

// Pixel statistics of the loaded tiles (same origin, so the canvas is clean).
function tilePixels() {
  let best = null;
  for (const img of document.querySelectorAll('img.leaflet-tile-loaded')) {
    if (!img.complete || !img.naturalWidth) continue;
    const canvas = document.createElement('canvas');
    canvas.width = img.naturalWidth;
    canvas.height = img.naturalHeight;
    const context = canvas.getContext('2d');
    context.drawImage(img, 0, 0);
    const {data} = context.getImageData(0, 0, canvas.width, canvas.height);
    let opaque = 0, sum = 0, sum2 = 0;
    for (let i = 0; i < data.length; i += 4) {
      if (data[i + 3] < 128) continue;
      const v = (data[i] + data[i + 1] + data[i + 2]) / 3;
      opaque++;
      sum += v;
      sum2 += v * v;
    }
    const mean = opaque ? sum / opaque : 0;
    const stats = {src: img.src, opaque: opaque / (data.length / 4), mean, std: opaque ? Math.sqrt(Math.max(0, sum2 / opaque - mean * mean)) : 0};
    if (!best || stats.opaque * stats.std > best.opaque * best.std) best = stats;
  }
  return best;
}

// A track point from early in the survey (surely painted by now), centred,
// on the map itself: not under a mark, whose click would open the mark.
function earlyTrackPoint(page) {
  return page.evaluate(() => {
    const {map, track} = window.seamap;
    const points = track.points;
    const box = map.getContainer().getBoundingClientRect();
    for (let i = Math.floor(points.length / 3); i < points.length; ++i) {
      map.setView(points[i], map.getZoom(), {animate: false});
      const p = map.latLngToContainerPoint(points[i]);
      const at = {x: box.left + p.x + 3, y: box.top + p.y + 3};
      const under = document.elementFromPoint(at.x, at.y);
      if (under && !under.closest('.leaflet-marker-pane, .leaflet-popup-pane, .leaflet-control-container')) return at;
    }
    throw new Error('no track point clear of marks');
  });
}

await runE2E({name: 'console', timeoutMs: TOTAL_TIMEOUT_MS}, async t => {
  const {checks, seamap, sourceDir, work, shot} = t;
  if (!URL_GIVEN && !fs.existsSync(seamap)) throw new Error(`no seamap binary at ${seamap}`);
  if (!fs.existsSync(path.join(sourceDir, 'web', 'vendor', 'leaflet', 'leaflet.js'))) {
    throw new Error('web/vendor/leaflet is missing: run scripts/setup_web.sh');
  }

  const {base, token} = await startServer(t);
  checks.ok('server is listening', base);

  const browser = await t.launchBrowser();
  const page = await browser.newPage({viewport: {width: 1280, height: 800}});
  page.setDefaultTimeout(10000);
  const pageErrors = [];
  page.on('pageerror', error => pageErrors.push(error.message));
  page.on('console', message => {
    if (message.type() === 'error') pageErrors.push(`console: ${message.text()}`);
  });
  await watchIntervals(page);   // a layer taken off the map must leave no interval running
  checks.diagnose = () => page.evaluate(() => {
    const popups = [...document.querySelectorAll('.leaflet-popup')].map(p =>
      `popup opacity ${getComputedStyle(p).opacity}: ${p.textContent.replace(/\s+/g, ' ').slice(0, 80)}`);
    const {map} = window.seamap;
    return [`toast "${document.querySelector('#toast')?.textContent}"`,
      `token state "${document.querySelector('#token-state')?.textContent}"`,
      `mode ${document.querySelector('input[name="mode"]:checked')?.id}, zoom ${map.getZoom()}, moving ${map._panAnim?._inProgress ?? false}`,
      ...popups].join('\n');
  });

  const loaded = await checks.run('console loads', async () => {
    await page.goto(base, {waitUntil: 'domcontentloaded'});
    await page.waitForSelector('body[data-ready="true"]', {timeout: 20000});
    await page.evaluate(() => { window.__e2eSamePage = true; });
    const hasLeaflet = await page.evaluate(() => Boolean(window.L && window.seamap && window.seamap.map));
    if (!hasLeaflet) throw new Error('Leaflet or the console did not start');
    if (!await page.$eval('#catalogue-link', a => a.hidden)) throw new Error('a link to a catalogue that is not there');
    return `status ${await page.textContent('#progress-label')}`;
  });
  if (!loaded) throw new Error('the console did not load; the other checks need it');

  await checks.run('track grows while the replay runs', async () => {
    const count = () => page.$eval('#track-count', el => Number(el.dataset.count));
    const first = await count();
    if (await page.$eval('#progress', el => el.dataset.state) === 'complete') {
      throw new Error('the replay ended before the browser watched it: lower SEAMAP_E2E_SPEED');
    }
    const later = await waitFor('more track points', async () => {
      const n = await count();
      return n > first && n >= 2 ? n : 0;
    }, {timeoutMs: 20000});
    const line = await page.evaluate(() => window.seamap.track.points.length);
    if (line !== later && line < later) throw new Error(`polyline has ${line} points, counter ${later}`);
    return `${first} -> ${later} points`;
  });

  await checks.run('an uncorrected mission: one track, no legend, the nav track is the same', async () => {
    if (await page.$('.track-legend') || await page.$('path.track-nav')) throw new Error('a navigation track is drawn');
    const get = async source => (await fetch(new URL(`api/track?source=${source}`, base))).json();
    const [nav, estimated] = await Promise.all([get('nav'), get('estimated')]);
    if (nav.properties.corrected !== false) throw new Error(`properties.corrected is ${nav.properties.corrected}`);
    const n = Math.min(nav.geometry.coordinates.length, estimated.geometry.coordinates.length);
    if (JSON.stringify(nav.geometry.coordinates.slice(0, n)) !== JSON.stringify(estimated.geometry.coordinates.slice(0, n))) {
      throw new Error('source=nav differs from source=estimated');
    }
    return `${n} points alike`;
  });

  await checks.run('a tile event refreshes a tile in place', async () => {
    // Follow the vehicle at the finest native zoom, where tiles are being
    // painted and repainted, and tag the tile elements now on the page.
    await page.check('#follow');
    await page.evaluate(() => {
      const {map, layers} = window.seamap;
      map.setZoom(layers.main.options.maxNativeZoom, {animate: false});
    });
    const found = await waitFor('a refreshed tile', () => page.evaluate(() => {
      for (const img of document.querySelectorAll('img.leaflet-tile')) {
        if (!img.__e2eSeen) img.__e2eSeen = {src: img.src};
      }
      for (const img of document.querySelectorAll('img.leaflet-tile[data-refreshed]')) {
        const before = img.__e2eSeen && img.__e2eSeen.src;
        if (before && before !== img.src && img.src.includes(`v=${img.dataset.version}`)) {
          return {before, after: img.src, samePage: window.__e2eSamePage === true};
        }
      }
      return null;
    }), {timeoutMs: 25000});
    if (!found.samePage) throw new Error('the page was reloaded');
    const short = url => url.replace(/^https?:\/\/[^/]+/, '');
    return `${short(found.before)} -> ${short(found.after)}`;
  });

  await checks.run('the tile layer stops its timer when removed, and refreshes tiles again when added back', async () => {
    await page.uncheck('#follow');   // the view holds still: the tile picked stays on screen
    const counts = await page.evaluate(() => {
      const {map, layers} = window.seamap;
      const layersOnMap = () => {
        let n = 0;
        map.eachLayer(layer => { if (layer instanceof layers.main.constructor) n++; });
        return n;
      };
      const running = () => window.__e2eIntervalsFrom('/js/tile_layer.js');
      const before = {layers: layersOnMap(), intervals: running()};
      map.removeLayer(layers.main);
      const removed = {layers: layersOnMap(), intervals: running()};
      // Count Leaflet's tileload per tile: one more on a refresh would fade it in from transparent.
      layers.main.on('tileload', event => { event.tile.__e2eLoads = (event.tile.__e2eLoads || 0) + 1; });
      layers.main.addTo(map);
      const added = {layers: layersOnMap(), intervals: running()};
      return {before, removed, added};
    });
    const say = ({layers, intervals}) => `${layers} layers, ${intervals} intervals`;
    if (counts.before.intervals !== counts.before.layers || counts.removed.intervals !== counts.removed.layers ||
        counts.added.intervals !== counts.added.layers) {
      throw new Error(`before ${say(counts.before)}; removed ${say(counts.removed)}; added back ${say(counts.added)}`);
    }
    // A tile of the layer added back, loaded and well inside the view, gets a
    // new version as a tile event would bring it: its image is swapped in place.
    const picked = await waitFor('a loaded tile on screen', () => page.evaluate(() => {
      const {map, layers} = window.seamap;
      const box = map.getContainer().getBoundingClientRect();
      for (const img of layers.main.getContainer().querySelectorAll('img.leaflet-tile-loaded')) {
        const r = img.getBoundingClientRect();
        if (r.left < box.left || r.right > box.right || r.top < box.top || r.bottom > box.bottom) continue;
        const [z, x, y] = img.dataset.tile.split('/').map(Number);
        if (z !== layers.main.tileZoom()) continue;   // a tile of the level zoomed from, about to go
        img.__e2ePicked = {src: img.src, refreshed: Number(img.dataset.refreshed || 0)};
        layers.main.refreshTile({layer: '', z, x, y, version: `e2e-${Date.now()}`});
        return img.dataset.tile;
      }
      return null;
    }), {timeoutMs: 10000});
    const swapped = await waitFor(`tile ${picked} swapped`, () => page.evaluate(tile => {
      const img = window.seamap.layers.main.getContainer().querySelector(`img[data-tile="${tile}"]`);
      if (!img || !img.__e2ePicked) throw Object.assign(new Error(`tile ${tile} left the page`), {fatal: true});
      if (Number(img.dataset.refreshed || 0) <= img.__e2ePicked.refreshed || img.src === img.__e2ePicked.src) return null;
      return {loads: img.__e2eLoads || 0, src: img.src, version: img.dataset.version};
    }, picked), {timeoutMs: 15000});
    if (swapped.loads > 1) throw new Error(`tile ${picked} was faded in again on its refresh (${swapped.loads} tileload events)`);
    if (!swapped.src.includes(`v=${swapped.version}`)) throw new Error(`tile ${picked} shows ${swapped.src}, version ${swapped.version}`);
    return `${say(counts.before)}, ${say(counts.removed)} after removal; ${picked} -> v=${swapped.version}`;
  });

  await checks.run('tiles load and are not blank', async () => {
    const stats = await waitFor('a loaded tile with seabed texture', async () => {
      const s = await page.evaluate(tilePixels);
      return s && s.opaque > 0.05 && s.std > 2 ? s : null;
    }, {timeoutMs: 20000});
    const tileUrl = new URL(stats.src);
    const response = await fetch(tileUrl);
    if (response.status !== 200) throw new Error(`tile fetch answered ${response.status}`);
    if (!response.headers.get('etag')) throw new Error('tile without ETag');
    return `${(stats.opaque * 100).toFixed(0)}% covered, grey level ${stats.mean.toFixed(0)} ± ${stats.std.toFixed(1)}`;
  });
  await shot(page, 'console-live');

  await checks.run('marks need the token', async () => {
    const status = await (await fetch(new URL('api/status', base))).json();
    if (!status.token_required) return 'server needs no token';
    const response = await fetch(new URL('api/detections', base), {
      method: 'POST',
      headers: {'Content-Type': 'application/json'},
      body: JSON.stringify({type: 'Feature', geometry: {type: 'Point', coordinates: [status.origin[1], status.origin[0]]}, properties: {class: 'nope'}}),
    });
    if (response.status !== 401) throw new Error(`POST without token answered ${response.status}`);
    return '401 without it';
  });

  await checks.run('a wrong token is reported as soon as it is entered, before any write', async () => {
    const status = await (await fetch(new URL('api/status', base))).json();
    if (!status.token_required) return 'server needs no token';
    const writes = [];
    const watch = request => {
      if (!['GET', 'HEAD', 'OPTIONS'].includes(request.method())) writes.push(`${request.method()} ${request.url()}`);
    };
    page.on('request', watch);
    try {
      const stateSays = text => page.waitForFunction(
        t => document.querySelector('#token-state').textContent.includes(t), text, {timeout: 5000});
      await page.fill('#token', `${token}-wrong`);
      await page.click('#token-form button[type="submit"]');
      await stateSays('wrong token');
      if (await page.evaluate(() => document.body.classList.contains('can-edit'))) {
        throw new Error('marks are still editable with the wrong token');
      }
      if (await page.evaluate(() => localStorage.getItem('seamap.token'))) throw new Error('the wrong token was kept');
      if (writes.length) throw new Error(`writes were sent: ${writes.join(', ')}`);
      await page.fill('#token', token);
      await page.click('#token-form button[type="submit"]');
      await stateSays('token set');
      if (!await page.evaluate(() => document.body.classList.contains('can-edit'))) {
        throw new Error('the right token did not allow editing');
      }
      if (writes.length) throw new Error(`writes were sent: ${writes.join(', ')}`);
    } finally {
      page.off('request', watch);
    }
    return 'said at once, no write sent';
  });

  await checks.run('a page of another site cannot write (403), even as a plain form', async () => {
    // The review's attack: a text/plain form POST from another site's page.
    const before = (await (await fetch(new URL('api/detections', base))).json()).features.length;
    const mark = JSON.stringify({type: 'Feature', geometry: {type: 'Point', coordinates: [0, 0]},
      properties: {class: 'forged', note: ''}}).slice(0, -3);
    const evil = http.createServer((request, response) => {
      response.setHeader('Content-Type', 'text/html');
      response.end(`<form method="POST" action="${base}api/detections" enctype="text/plain">` +
        `<input name='${mark}' value='"}}'></form><script>document.forms[0].submit()</script>`);
    });
    const evilPort = await freePort();
    await new Promise(resolve => evil.listen(evilPort, '127.0.0.1', resolve));
    const other = await browser.newPage();
    try {
      const answer = other.waitForResponse(r => r.url().endsWith('/api/detections') && r.request().method() === 'POST');
      await other.goto(`http://localhost:${evilPort}/`);  // localhost and 127.0.0.1 are different sites
      const response = await answer;
      if (response.status() !== 403) throw new Error(`the forged POST answered ${response.status()}`);
      const text = await response.text();
      if (!text.includes('cross-site write refused')) throw new Error(`answer: ${text}`);
      const after = (await (await fetch(new URL('api/detections', base))).json()).features.length;
      if (after !== before) throw new Error(`${after - before} detections were added`);
      return `403: ${JSON.parse(text).error.slice(0, 60)}...`;
    } finally {
      await other.close();
      evil.close();
    }
  });

  await checks.run('an operator mark appears live and its popup opens', async () => {
    await page.fill('#token', token);
    await page.click('#token-form button[type="submit"]');
    await page.uncheck('#follow');
    const pose = await page.evaluate(() => {
      const ll = window.seamap.track.points.at(-1) || window.seamap.map.getCenter();
      return {lat: ll.lat, lon: ll.lng};
    });
    const response = await fetch(new URL('api/detections', base), {
      method: 'POST',
      headers: {'Content-Type': 'application/json', Authorization: `Bearer ${token}`},
      body: JSON.stringify({type: 'Feature', geometry: {type: 'Point', coordinates: [pose.lon, pose.lat]},
        properties: {class: 'e2e-anchor', note: 'made by the e2e test', score: 1}}),
    });
    if (response.status !== 201) throw new Error(`POST answered ${response.status}: ${await response.text()}`);
    const feature = await response.json();
    const id = String(feature.id ?? feature.properties.id);
    const marker = `.leaflet-marker-icon[data-detection-id="${id}"]`;
    await page.waitForSelector(marker, {state: 'attached', timeout: 15000});
    await page.waitForSelector(`#detection-list li[data-id="${id}"]`, {state: 'attached', timeout: 5000});
    await page.evaluate(([lat, lon]) => window.seamap.map.setView([lat, lon], window.seamap.map.getZoom(), {animate: false}), [pose.lat, pose.lon]);
    await page.click(marker);
    await page.waitForSelector(`.leaflet-popup .detection-popup[data-id="${id}"]`, {timeout: 5000});
    const shown = (await page.textContent('.leaflet-popup .popup-class')).trim();
    if (shown !== 'e2e-anchor') throw new Error(`popup shows class "${shown}"`);
    const editable = await page.$('.leaflet-popup .mark-form');
    if (!editable) throw new Error('no edit form for an operator mark with the token set');
    await shot(page, 'console-detection');
    await page.evaluate(() => window.seamap.map.closePopup());
    return `mark ${id}`;
  });

  await checkConsoleTools({browser, page, checks, base, shot});

  await checks.run('a map click lists the covering photos and one opens full size', async () => {
    // Click a track point from early in the survey (surely painted by now).
    const point = await earlyTrackPoint(page);
    await page.check('#mode-photos');
    await sleep(300);
    await page.mouse.click(point.x, point.y);
    await page.waitForSelector('#photo-list[data-state="ready"]', {timeout: 10000});
    const count = await page.$eval('#photo-list', el => el.children.length);
    if (!count) throw new Error('no photo listed');
    await waitFor('a thumbnail', () => page.$eval('#photo-list li img', img => img.complete && img.naturalWidth > 0), {timeoutMs: 10000});
    await page.click('#photo-list li');
    await page.waitForSelector('#photo-full[data-state="loaded"]', {timeout: 10000});
    const size = await page.$eval('#photo-full', img => [img.naturalWidth, img.naturalHeight]);
    if (size[0] <= 256 && size[1] <= 256) throw new Error(`full-size photo is only ${size.join('x')}`);
    await shot(page, 'console-photo');
    if (count > 1) {
      const first = await page.getAttribute('#photo-full', 'src');
      await page.click('#photo-next');
      await waitFor('the next photo', async () => (await page.getAttribute('#photo-full', 'src')) !== first, {timeoutMs: 5000});
      await page.click('#photo-prev');
      await waitFor('the previous photo again', async () => (await page.getAttribute('#photo-full', 'src')) === first, {timeoutMs: 5000});
    }
    await page.click('#photo-viewer-close');
    return `${count} photos, full size ${size.join('x')}`;
  });

  await checks.run('phone width: the panel collapses and opens', async () => {
    await page.setViewportSize({width: 390, height: 760});
    await sleep(400);
    const hidden = await page.$eval('#panel', el => el.getBoundingClientRect().right <= 1);
    if (!hidden) throw new Error('panel still covers the map');
    await page.click('#panel-toggle');
    await sleep(400);
    const shown = await page.$eval('#panel', el => el.getBoundingClientRect().left >= -1);
    if (!shown) throw new Error('panel did not open');
    await shot(page, 'console-phone');
    await page.click('#panel-toggle');
    await sleep(400);
    // The progress stays on screen, and a map click shows the photo list.
    const progress = await page.$eval('#progress-label', el => {
      const r = el.getBoundingClientRect();
      return r.width > 20 && r.right <= window.innerWidth + 1 ? el.textContent : '';
    });
    if (!/frames/.test(progress)) throw new Error(`progress label not visible at phone width ("${progress}")`);
    const point = await earlyTrackPoint(page);
    await page.evaluate(() => { document.querySelector('#photo-list').dataset.state = ''; });
    await page.mouse.click(point.x, point.y);
    await page.waitForSelector('#photo-list[data-state="ready"]', {timeout: 10000});
    await sleep(400);
    const visible = await page.$eval('#photo-list li', li => {
      const r = li.getBoundingClientRect();
      return r.left >= -1 && r.right <= window.innerWidth + 1 && r.top >= 0 && r.bottom <= window.innerHeight + 1;
    });
    if (!visible) throw new Error('the photo list is not on screen after a map click');
    await shot(page, 'console-phone-photos');
    await page.click('#panel-toggle');
    return `progress "${progress}", photos on screen`;
  });

  await checks.run('no script errors on the page', async () => {
    const errors = pageErrors.filter(e => !/Failed to load resource/.test(e));
    if (errors.length) throw new Error(errors.join(' | '));
    return '';
  });

  if (!URL_GIVEN) {
    const tool = process.env.SEAMAP_CORRECTED_MISSION || path.join(path.dirname(seamap), 'corrected_mission');
    await checkCorrectedTracks({browser, checks, seamap, tool, work, sourceDir, shot});
  }
});

