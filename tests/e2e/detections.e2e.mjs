// A recogniser's detections in the operator console, headless Chromium
// against a real `seamap serve`: detections published into a built mission
// through DetectionRegistry::Publish (tests/tools/seed_detections), then
// class colours and legend, class and score filters, the list with scores,
// confirm/reject round trips to the server, the rejected toggle, and the
// photos that saw a detection opening in the photo viewer.
//
//   node tests/e2e/detections.e2e.mjs
//
// Environment: SEAMAP_BIN, SEAMAP_SEED_DETECTIONS (default build/seed_detections),
// SEAMAP_SOURCE_DIR, SEAMAP_ARTIFACTS (screenshots).
import path from 'node:path';
import {runE2E, run, waitFor, waitForOutput} from './harness.mjs';

await runE2E({name: 'detections', timeoutMs: 120000}, async ({checks, work, seamap, sourceDir, launchBrowser, start, shot, seeder}) => {
  const survey = path.join(work, 'survey');
  const map = path.join(work, 'map.mbtiles');
  await run(seamap, ['simulate', '--out', survey, '--frames', '24', '--line-length', '3', '--seed', '3', '--quiet']);
  await run(seamap, ['build', '--images', path.join(survey, 'photo'), '--nav', path.join(survey, 'nav.csv'),
    '--camera', path.join(survey, 'camera.json'), '--origin', '43.1,131.9', '--quiet', '--out', map]);
  const seeded = await run(seeder, [map]);
  const ids = String(seeded).trim().split(/\s+/).filter(id => /^\d+$/.test(id));
  if (ids.length !== 5) throw new Error(`seed_detections printed ${JSON.stringify(String(seeded))}`);
  checks.ok('five recogniser detections published into the mission', ids.join(' '));
  const token = `e2e-${process.pid}`;
  const server = start(seamap, ['serve', map, '--host', '127.0.0.1', '--port', '0',
    '--web', path.join(sourceDir, 'web'), '--token', token]);
  await waitForOutput(server, /serving http:\/\/127\.0\.0\.1:\d+\//, 20000);
  const base = /serving (http:\/\/127\.0\.0\.1:\d+\/)/.exec(server.output)[1];
  const api = async (method, url, body) => {
    const response = await fetch(new URL(url, base), {method,
      headers: {'Content-Type': 'application/json', Authorization: `Bearer ${token}`},
      body: body ? JSON.stringify(body) : undefined});
    if (!response.ok) throw new Error(`${method} ${url}: ${response.status} ${await response.text()}`);
    return response.json();
  };
  // An operator's mark beside them (diamond), at the first detection's place.
  const first = await api('GET', `api/detections/${ids[0]}`);
  const mark = await api('POST', 'api/detections', {type: 'Feature', geometry: first.geometry,
    properties: {class: 'tyre', note: 'seen by the diver'}});
  const markId = String(mark.id);

  const browser = await launchBrowser();
  const page = await browser.newPage({viewport: {width: 1200, height: 760}});
  page.setDefaultTimeout(10000);
  const errors = [];
  page.on('pageerror', e => errors.push(e.message));
  // Under a failed check: the popups, the toast and each marker's classes.
  checks.diagnose = () => page.evaluate(() => [
    `toast "${document.querySelector('#toast')?.textContent}"`,
    ...[...document.querySelectorAll('.leaflet-popup')].map(p =>
      `popup opacity ${getComputedStyle(p).opacity}: ${p.textContent.replace(/\s+/g, ' ').slice(0, 100)}`),
    ...[...document.querySelectorAll('.leaflet-marker-icon')].map(m => `marker ${m.className}`),
  ].join('\n'));
  await checks.run('the console opens and takes the token', async () => {
    await page.goto(base);
    await page.waitForSelector('body[data-ready="true"]');
    await page.fill('#token', token);
    await page.click('#token-form button[type="submit"]');
    await page.waitForSelector('body.can-edit', {state: 'attached'});
    return '';
  });
  const listIds = () => page.$$eval('#detection-list li', lis => lis.map(li => li.dataset.id));
  const markerOf = id => `.leaflet-marker-icon[data-detection-id="${id}"]`;

  await checks.run('recognised objects are round in their class colour, marks diamonds, with a legend', async () => {
    await page.waitForFunction(n => document.querySelectorAll('.leaflet-marker-icon[data-detection-id]').length === n, 6);
    const icons = await page.$$eval('.leaflet-marker-icon[data-detection-id]', els => els.map(e => {
      const span = e.querySelector('span');
      const style = getComputedStyle(span);
      return {id: e.dataset.detectionId, operator: e.classList.contains('operator'), colour: style.backgroundColor,
        radius: style.borderRadius, transform: style.transform, cls: span.title};
    }));
    const colours = {};
    for (const icon of icons) {
      if (icon.operator !== (icon.id === markId)) throw new Error(`wrong shape: ${JSON.stringify(icon)}`);
      if (!icon.operator && icon.radius !== '50%') throw new Error(`not round: ${JSON.stringify(icon)}`);
      if (icon.operator && icon.transform === 'none') throw new Error(`mark not a diamond: ${JSON.stringify(icon)}`);
      (colours[icon.cls] ??= new Set()).add(icon.colour);
    }
    for (const [cls, set] of Object.entries(colours)) if (set.size !== 1) throw new Error(`${cls}: colours ${[...set]}`);
    const distinct = new Set(Object.values(colours).map(s => [...s][0]));
    if (distinct.size !== 3) throw new Error(`3 classes, ${distinct.size} colours`);
    const legend = await page.$$eval('.class-legend .entry', els => els.map(e => e.textContent.trim()));
    if (legend.join('|') !== 'crate (2)|pipe (1)|tyre (3)') throw new Error(`legend: ${legend}`);
    return `${icons.length} markers, legend ${legend.join(', ')}`;
  });

  await checks.run('the list shows scores; class and score filters narrow map and list', async () => {
    const scores = await page.$$eval('#detection-list li .list-score', els => els.map(e => e.textContent.trim()));
    for (const s of ['95%', '80%', '65%', '50%', '45%', 'mark']) if (!scores.includes(s)) throw new Error(`list: ${scores}`);
    await page.selectOption('#detection-class', 'tyre');
    await waitFor('only tyres listed', async () => (await listIds()).length === 3);
    await page.selectOption('#detection-class', '');
    await page.$eval('#detection-score', el => { el.value = '60'; el.dispatchEvent(new Event('input')); });
    await waitFor('scores >= 0.6 and the mark', async () => (await listIds()).length === 4);
    const markers = await page.$$eval('.leaflet-marker-icon[data-detection-id]', els => els.length);
    if (markers !== 4) throw new Error(`${markers} markers on the map with the score filter`);
    const label = await page.textContent('#detection-score-value');
    await page.$eval('#detection-score', el => { el.value = '0'; el.dispatchEvent(new Event('input')); });
    await waitFor('all back', async () => (await listIds()).length === 6);
    return `score filter ${label.trim()}: 4 shown`;
  });

  const openPopup = async id => {
    await page.click(`#detection-list li[data-id="${id}"]`);
    await page.waitForSelector(`.leaflet-popup .detection-popup[data-id="${id}"]`);
  };

  await checks.run('reject and confirm in the popup reach the server; rejected ones fade or hide', async () => {
    const crate = ids[1];
    await openPopup(crate);
    await page.click(`.leaflet-popup .detection-popup[data-id="${crate}"] button.reject`);
    await page.waitForSelector(`${markerOf(crate)}.status-rejected`, {state: 'attached'});
    await page.waitForSelector(`.leaflet-popup .detection-popup[data-id="${crate}"] .popup-status:text-is("rejected")`);
    const stored = await api('GET', `api/detections/${crate}`);
    if (stored.properties.status !== 'rejected') throw new Error(`server has ${stored.properties.status}`);
    const opacity = await page.$eval(markerOf(crate), e => Number(getComputedStyle(e).opacity));
    if (!(opacity < 0.6)) throw new Error(`rejected marker opacity ${opacity}`);
    await page.evaluate(() => window.seamap.map.closePopup());
    await page.uncheck('#detection-rejected');
    await waitFor('rejected one hidden', async () => !(await listIds()).includes(crate) && !(await page.$(markerOf(crate))));
    await page.check('#detection-rejected');
    await waitFor('rejected one back', async () => (await listIds()).includes(crate));

    const pipe = ids[2];
    await openPopup(pipe);
    await page.click(`.leaflet-popup .detection-popup[data-id="${pipe}"] button.confirm`);
    await page.waitForSelector(`.leaflet-popup .detection-popup[data-id="${pipe}"] .popup-status:text-is("confirmed")`);
    const confirmed = await api('GET', `api/detections/${pipe}`);
    if (confirmed.properties.status !== 'confirmed') throw new Error(`server has ${confirmed.properties.status}`);
    const patched = await fetch(new URL(`api/detections/${pipe}`, base), {method: 'PATCH',
      headers: {'Content-Type': 'application/json', Authorization: `Bearer ${token}`}, body: '{"class":"rock"}'});
    if (patched.status !== 403) throw new Error(`changing a recogniser's class answered ${patched.status}`);
    await shot(page, 'detections-review');
    return `crate ${crate} rejected, pipe ${pipe} confirmed`;
  });

  await checks.run('the photos that saw a detection open in the photo viewer', async () => {
    const tyre = ids[0];
    await openPopup(tyre);
    const strip = `.leaflet-popup .detection-popup[data-id="${tyre}"] .photo-strip a`;   // not a closing popup's
    const frames = await page.$$eval(strip, as => as.map(a => a.dataset.frame));
    const expected = first.properties.frames.map(String);
    if (frames.join() !== expected.join()) throw new Error(`strip ${frames}, detection frames ${expected}`);
    await page.click(`${strip} >> nth=1`);
    await page.waitForSelector('#photo-viewer:not([hidden])');
    await page.waitForSelector('#photo-full[data-state="loaded"]');
    const src = await page.getAttribute('#photo-full', 'src');
    if (!src.endsWith(`/api/frames/${expected[1]}/image`)) throw new Error(`viewer shows ${src}`);
    await page.click('#photo-next');
    await page.waitForFunction(want => document.querySelector('#photo-full').src.endsWith(want), `/api/frames/${expected[2]}/image`);
    await shot(page, 'detections-photo');
    await page.click('#photo-viewer-close');
    return `frames ${frames.join(', ')}`;
  });

  await checks.run('the detections CSV export carries status, model, size and frames', async () => {
    const csv = await page.evaluate(async () => {
      const {detectionsCsv} = await import('/js/export.js');
      return detectionsCsv(await (await fetch('/api/detections')).json());
    });
    const [header, ...rows] = csv.trim().split('\n');
    if (!header.endsWith(',status,model,size_ew_m,size_ns_m,frames')) throw new Error(header);
    const crate = rows.find(r => r.startsWith(`${ids[1]},crate,`));
    if (!crate || !/,rejected,seamap-tiles\.onnx@e2e0,0\.6,0\.4,\d+ \d+ \d+$/.test(crate)) throw new Error(crate);
    return `${rows.length} rows`;
  });

  await checks.run('no script errors on the page', async () => {
    if (errors.length) throw new Error(errors.join(' | '));
    return '';
  });
});
