// `seamap serve FOLDER` in headless Chromium: the mission picker lists every
// map of the folder (a broken one with its reason), shows the chosen
// mission's tiles from its own prefix, opens a mission in the full operator
// console (its track, API and read-only marks under /missions/{id}/), picks up
// a dive copied in later, and follows a mission another process is building
// with live events.
import fs from 'node:fs';
import path from 'node:path';
import {runE2E, run, waitFor, waitForOutput} from './harness.mjs';

// The watchdog under ctest's TIMEOUT 150, so the children are killed.
await runE2E({name: 'catalogue', timeoutMs: 140000}, async ({checks, work, seamap, sourceDir, launchBrowser, start, shot, seeder}) => {
  const survey = path.join(work, 'survey');
  const map = path.join(work, 'map.mbtiles');
  const folder = path.join(work, 'missions');
  await run(seamap, ['simulate', '--out', survey, '--frames', '12', '--line-length', '2', '--seed', '3', '--quiet']);
  await run(seamap, ['build', '--images', path.join(survey, 'photo'), '--nav', path.join(survey, 'nav.csv'),
    '--camera', path.join(survey, 'camera.json'), '--origin', '43.1,131.9', '--quiet', '--out', map]);
  fs.mkdirSync(folder);
  fs.copyFileSync(map, path.join(folder, 'dive_a.mbtiles'));
  await run(seeder, [path.join(folder, 'dive_a.mbtiles'), '--stereo']);  // an object located by stereo, with a heading
  fs.copyFileSync(map, path.join(folder, 'dive_b.mbtiles'));
  fs.writeFileSync(path.join(folder, 'broken.mbtiles'), 'half-copied');
  const server = start(seamap, ['serve', folder, '--host', '127.0.0.1', '--port', '0',
    '--web', path.join(sourceDir, 'web')]);
  await waitForOutput(server, /serving http:\/\/127\.0\.0\.1:\d+\//, 20000);
  const base = /serving (http:\/\/127\.0\.0\.1:\d+\/)/.exec(server.output)[1];
  checks.ok('catalogue server is listening', base);

  const browser = await launchBrowser();
  const page = await browser.newPage({viewport: {width: 1100, height: 700}});
  page.setDefaultTimeout(15000);
  const errors = [];
  page.on('pageerror', e => errors.push(e.message));
  const tileRequests = [];
  page.on('request', r => { if (/\/missions\/[^/]+\/tiles\/\d+/.test(r.url())) tileRequests.push(r.url()); });

  await checks.run('the picker lists every mission, the broken one with its reason', async () => {
    await page.goto(base);
    await page.waitForSelector('body[data-ready="true"]');
    const items = await page.$$eval('#missions li', lis => lis.map(li => ({id: li.dataset.id,
      available: li.dataset.available, text: li.textContent})));
    if (items.length !== 3) throw new Error(JSON.stringify(items));
    const broken = items.find(i => i.id === 'broken');
    if (!broken || broken.available !== 'false' || !/not a database|cannot open/.test(broken.text)) {
      throw new Error(JSON.stringify(broken));
    }
    return items.map(i => i.id).join(', ');
  });

  await checks.run('picking a mission shows its tiles from its own prefix', async () => {
    await page.click('#missions li[data-id="dive_b"]');
    await page.waitForSelector('body[data-mission="dive_b"]');
    await page.waitForFunction(() => document.querySelectorAll('img.leaflet-tile-loaded').length > 0);
    await waitFor('tiles of dive_b', () => tileRequests.some(u => u.includes('/missions/dive_b/tiles/')));
    const wrong = tileRequests.filter(u => !u.includes('/missions/dive_b/'));
    if (wrong.length) throw new Error(`tiles of another mission: ${wrong[0]}`);
    const loaded = await page.$$eval('img.leaflet-tile-loaded', imgs => imgs.filter(i => i.naturalWidth === 256).length);
    if (!loaded) throw new Error('no tile drawn');
    if (!page.url().endsWith('#dive_b')) throw new Error(page.url());
    await shot(page, 'catalogue-picker');
    return `${loaded} tiles drawn`;
  });

  await checks.run('a mission opens in the operator console under its own prefix', async () => {
    const apiRequests = [];
    const listen = r => { if (r.url().includes('/api/')) apiRequests.push(new URL(r.url()).pathname); };
    page.on('request', listen);
    const href = await page.$eval('#missions li[data-id="dive_a"] a.console', a => a.getAttribute('href'));
    if (href !== '/missions/dive_a/') throw new Error(`console link ${href}`);
    await page.goto(new URL(href, base).href);
    await page.waitForSelector('body[data-ready="true"]');
    const status = await (await fetch(new URL('missions/dive_a/api/status', base))).json();
    const shown = await waitFor('track drawn', async () => {
      const n = await page.$eval('#track-count', el => Number(el.dataset.count));
      return n === status.track_points ? n : null;
    });
    await page.waitForFunction(() => document.querySelectorAll('img.leaflet-tile-loaded').length > 0);
    page.off('request', listen);
    const elsewhere = apiRequests.filter(p => !p.startsWith('/missions/dive_a/api/'));
    if (elsewhere.length) throw new Error(`API asked outside the mission: ${elsewhere.join(', ')}`);
    if (!apiRequests.includes('/missions/dive_a/api/events')) throw new Error(`no event stream: ${apiRequests.join(', ')}`);
    if (await page.$eval('#progress', el => el.dataset.state) !== 'complete') throw new Error('state is not complete');
    if (await page.$eval('#catalogue-link', a => a.hidden || a.getAttribute('href') !== '/')) throw new Error('no way back to the missions');
    // A catalogue is read-only: a mark is refused, and the console says so instead of offering to write.
    const post = await fetch(new URL('missions/dive_a/api/detections', base), {method: 'POST',
      headers: {'Content-Type': 'application/json'},
      body: JSON.stringify({type: 'Feature', geometry: {type: 'Point', coordinates: [131.9, 43.1]}, properties: {class: 'tyre'}})});
    if (post.status < 400) throw new Error(`a write was accepted: ${post.status}`);
    // The object located by stereo: its mark carries an arrow along its heading, its popup heading and depth.
    const arrow = await page.waitForSelector('.leaflet-marker-icon .heading', {timeout: 5000});
    const turn = await arrow.evaluate(b => [b.dataset.heading, b.style.transform]);
    if (turn[0] !== '123.7' || !turn[1].includes('rotate(123.7deg)')) throw new Error(`arrow ${turn}`);
    await page.click('.leaflet-marker-icon:has(.heading)');
    const heading = await page.textContent('.leaflet-popup .popup-heading');
    if (heading !== '123.7°') throw new Error(`popup heading "${heading}"`);
    const sigma = await page.textContent('.leaflet-popup .popup-sigma');  // its stored uncertainty
    if (sigma !== '± 12.3 mm') throw new Error(`popup uncertainty "${sigma}"`);
    await page.evaluate(() => window.seamap.map.closePopup());
    const other = await fetch(new URL('missions/nope/api/status', base));
    if (other.status !== 404) throw new Error(`unknown mission: ${other.status}`);
    await shot(page, 'catalogue-console');
    return `${shown} track points, ${apiRequests.length} API requests under the prefix, write refused ${post.status}, ` +
      `stereo mark heading ${heading}`;
  });

  await checks.run('a mission another process is building keeps its live events', async () => {
    const live = path.join(work, 'live_survey');
    await run(seamap, ['simulate', '--out', live, '--frames', '60', '--line-length', '3', '--seed', '4', '--quiet']);
    const replay = start(seamap, ['replay', live, '--out', path.join(folder, 'live.mbtiles'), '--speed', '1',
      '--port', '0', '--host', '127.0.0.1', '--exit-when-done', '--quiet', '--web', path.join(sourceDir, 'web')]);
    await waitFor('live mission listed as building', async () => {
      const missions = await (await fetch(new URL('api/missions', base))).json();
      return missions.find(m => m.id === 'live' && m.state === 'building');
    }, {timeoutMs: 10000});
    await page.goto(new URL('missions/live/', base).href);
    await page.waitForSelector('body[data-ready="true"]');
    await page.waitForSelector('#progress[data-state="building"]', {timeout: 10000});
    const count = () => page.$eval('#track-count', el => Number(el.dataset.count));
    const first = await count();
    const later = await waitFor('track points arriving as events', async () => {
      const n = await count();
      return n > first ? n : null;
    }, {timeoutMs: 15000});
    await page.waitForSelector('#progress[data-state="complete"]', {timeout: 30000});
    const final = await count();
    const status = await (await fetch(new URL('missions/live/api/status', base))).json();
    if (final !== status.track_points || final < later) throw new Error(`console ${final}, server ${status.track_points}`);
    return `${first} -> ${later} -> ${final} track points, then complete`;
  });

  await checks.run('a dive copied into the folder appears in the picker', async () => {
    await page.goto(base);
    await page.waitForSelector('body[data-ready="true"]');
    fs.copyFileSync(map, path.join(folder, 'dive c.mbtiles'));
    await page.waitForSelector('#missions li[data-id="dive-c"]', {timeout: 10000});
    return 'dive-c';
  });

  await checks.run('no script errors on the page', async () => {
    if (errors.length) throw new Error(errors.join(' | '));
    return '';
  });
});
