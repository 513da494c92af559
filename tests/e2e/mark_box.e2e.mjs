// An operator draws a box around an object the recogniser missed and gives it
// a class the model does not know (issue 32): headless Chromium against a real
// `seamap serve`. In mark mode a drag draws the box, the new-mark form takes a
// new class, and the server stores the mark with its box (size and ring
// matching the drag) and offers the class afterwards; a plain click still
// makes a point mark.
//
//   node tests/e2e/mark_box.e2e.mjs
//
// Environment: SEAMAP_BIN, SEAMAP_SOURCE_DIR, SEAMAP_ARTIFACTS (screenshots).
import path from 'node:path';
import {runE2E, run, waitForOutput} from './harness.mjs';

const sleep = ms => new Promise(resolve => setTimeout(resolve, ms));

await runE2E({name: 'mark_box', timeoutMs: 120000}, async ({checks, work, seamap, sourceDir, launchBrowser, start, shot}) => {
  const survey = path.join(work, 'survey');
  const map = path.join(work, 'map.mbtiles');
  await run(seamap, ['simulate', '--out', survey, '--frames', '24', '--line-length', '3', '--seed', '3', '--quiet']);
  await run(seamap, ['build', '--images', path.join(survey, 'photo'), '--nav', path.join(survey, 'nav.csv'),
    '--camera', path.join(survey, 'camera.json'), '--origin', '43.1,131.9', '--quiet', '--out', map]);
  const token = `e2e-${process.pid}`;
  const server = start(seamap, ['serve', map, '--host', '127.0.0.1', '--port', '0',
    '--web', path.join(sourceDir, 'web'), '--token', token]);
  await waitForOutput(server, /serving http:\/\/127\.0\.0\.1:\d+\//, 20000);
  const base = /serving (http:\/\/127\.0\.0\.1:\d+\/)/.exec(server.output)[1];
  const get = async url => (await fetch(new URL(url, base))).json();

  const browser = await launchBrowser();
  const page = await browser.newPage({viewport: {width: 1200, height: 760}});
  page.setDefaultTimeout(10000);
  const errors = [];
  page.on('pageerror', e => errors.push(e.message));
  checks.diagnose = () => page.evaluate(() => [
    `toast "${document.querySelector('#toast')?.textContent}"`,
    `mode ${document.body.dataset.mode}`,
    ...[...document.querySelectorAll('.leaflet-popup')].map(p => `popup: ${p.textContent.replace(/\s+/g, ' ').slice(0, 100)}`),
  ].join('\n'));

  await checks.run('the console opens and takes the token', async () => {
    await page.goto(base);
    await page.waitForSelector('body[data-ready="true"]');
    await page.fill('#token', token);
    await page.click('#token-form button[type="submit"]');
    await page.waitForSelector('body.can-edit', {state: 'attached'});
    await page.uncheck('#follow').catch(() => {});
    return '';
  });

  let drawn = null;   // the drag's corners as lat/lon
  let id = null;
  await checks.run('a drag in mark mode draws a box and the mark gets a new class with that box', async () => {
    await page.check('#mode-mark');
    await sleep(500);
    const r = await page.$eval('#map', el => {
      const b = el.getBoundingClientRect();
      return {x: b.left + b.width * 0.4, y: b.top + b.height * 0.4};
    });
    const corners = [{x: r.x, y: r.y}, {x: r.x + 90, y: r.y + 60}];
    drawn = await page.evaluate(([a, b]) => {
      const {map} = window.seamap;
      const box = map.getContainer().getBoundingClientRect();
      return [a, b].map(p => map.containerPointToLatLng([p.x - box.left, p.y - box.top]));
    }, corners);
    const centreBefore = await page.evaluate(() => window.seamap.map.getCenter());
    await page.mouse.move(corners[0].x, corners[0].y);
    await page.mouse.down();
    for (let k = 1; k <= 6; ++k)
      await page.mouse.move(corners[0].x + 15 * k, corners[0].y + 10 * k);
    await page.waitForSelector('path.drawing-box', {state: 'attached'});
    await page.mouse.up();
    await page.waitForSelector('.leaflet-popup .new-mark', {timeout: 5000});
    const title = await page.textContent('.leaflet-popup .new-mark h3');
    if (!/box/.test(title)) throw new Error(`the form says "${title}"`);
    const centreAfter = await page.evaluate(() => window.seamap.map.getCenter());
    if (Math.abs(centreAfter.lat - centreBefore.lat) > 1e-9 || Math.abs(centreAfter.lng - centreBefore.lng) > 1e-9)
      throw new Error('the map panned while the box was drawn');
    await shot(page, 'mark-box-drawn');
    await page.fill('.leaflet-popup .new-mark input[name="class"]', 'drum');
    await page.click('.leaflet-popup .new-mark button[type="submit"]');
    const li = await page.waitForSelector('#detection-list li[data-class="drum"]', {state: 'attached', timeout: 5000});
    id = await li.getAttribute('data-id');
    const stored = await get(`api/detections/${id}`);
    const p = stored.properties;
    if (p.source !== 'operator' || p.class !== 'drum') throw new Error(JSON.stringify(p));
    if (!Array.isArray(p.box) || p.box.length !== 5) throw new Error(`box ${JSON.stringify(p.box)}`);
    const lons = p.box.map(c => c[0]), lats = p.box.map(c => c[1]);
    const want = {w: Math.min(drawn[0].lng, drawn[1].lng), e: Math.max(drawn[0].lng, drawn[1].lng),
      s: Math.min(drawn[0].lat, drawn[1].lat), n: Math.max(drawn[0].lat, drawn[1].lat)};
    const got = {w: Math.min(...lons), e: Math.max(...lons), s: Math.min(...lats), n: Math.max(...lats)};
    const pxDeg = (want.e - want.w) / 90;   // one screen pixel in degrees of longitude
    for (const k of ['w', 'e', 's', 'n'])
      if (Math.abs(got[k] - want[k]) > 2 * pxDeg) throw new Error(`box ${k} ${got[k]} vs drawn ${want[k]}`);
    const [lon, lat] = stored.geometry.coordinates;
    if (lon < got.w || lon > got.e || lat < got.s || lat > got.n) throw new Error('the point is outside its box');
    if (!(p.size_m[0] > 0 && p.size_m[1] > 0)) throw new Error(`size_m ${p.size_m}`);
    await page.waitForSelector('path.mark-box', {state: 'attached'});
    return `mark ${id}: ${p.size_m.map(v => v.toFixed(3)).join(' x ')} m`;
  });

  await checks.run('the new class is the mission\'s and offered afterwards', async () => {
    const status = await get('api/status');
    if (!status.classes?.includes('drum')) throw new Error(`status classes ${JSON.stringify(status.classes)}`);
    await page.waitForFunction(() => [...document.querySelectorAll('#class-names option')].some(o => o.value === 'drum'));
    return status.classes.join(', ');
  });

  await checks.run('a plain click in mark mode still makes a point mark', async () => {
    await page.keyboard.press('Escape');
    await page.evaluate(() => window.seamap.map.closePopup());
    const r = await page.$eval('#map', el => {
      const b = el.getBoundingClientRect();
      return {x: b.left + b.width * 0.7, y: b.top + b.height * 0.7};
    });
    await sleep(300);
    await page.mouse.click(r.x, r.y);
    await page.waitForSelector('.leaflet-popup .new-mark', {timeout: 5000});
    const title = await page.textContent('.leaflet-popup .new-mark h3');
    if (title !== 'new mark') throw new Error(`the form says "${title}"`);
    await page.fill('.leaflet-popup .new-mark input[name="class"]', 'net');
    await page.click('.leaflet-popup .new-mark button[type="submit"]');
    const li = await page.waitForSelector('#detection-list li[data-class="net"]', {state: 'attached', timeout: 5000});
    const stored = await get(`api/detections/${await li.getAttribute('data-id')}`);
    if (stored.properties.box !== null) throw new Error(`a point mark with box ${JSON.stringify(stored.properties.box)}`);
    return '';
  });

  await checks.run('no script errors on the page', async () => {
    if (errors.length) throw new Error(errors.join(' | '));
    return '';
  });
});
