// Issue 33, row 4: every text that comes from a map, a file name or a record
// reaches the page as text. A mission whose attribution, name, layer name,
// photo file name, detection class/model/source/status/note and operator
// mark carry HTML payloads (`<img src=x onerror=window.__pwned='WHERE'>`)
// is opened in headless Chromium: in the operator console (load, footprint
// tooltips, the photo viewer and list, detection and mark popups), in the
// catalogue's picker (file and mission names, attribution) and in
// pmtiles.html (attribution, object popups). No payload may run
// (window.__pwned stays undefined) and each text must be shown as typed.
import fs from 'node:fs';
import http from 'node:http';
import path from 'node:path';
import {runE2E, run, sleep, stopProcess, waitForOutput} from './harness.mjs';

const payload = where => `<img src=x onerror=window.__pwned='${where}'>`;
const sqlText = text => `'${text.replace(/'/g, "''")}'`;

const TYPES = {'.html': 'text/html', '.js': 'text/javascript', '.css': 'text/css', '.png': 'image/png'};

// A static host answering single byte ranges (what pmtiles.html needs).
function staticServer(root) {
  const server = http.createServer((req, res) => {
    const file = path.join(root, decodeURIComponent(new URL(req.url, 'http://x').pathname));
    if (!file.startsWith(root) || !fs.existsSync(file) || !fs.statSync(file).isFile()) return res.writeHead(404).end();
    const size = fs.statSync(file).size;
    const type = TYPES[path.extname(file)] || 'application/octet-stream';
    const range = /^bytes=(\d+)-(\d*)$/.exec(req.headers.range || '');
    const start = range ? Number(range[1]) : 0;
    const end = range ? Math.min(range[2] ? Number(range[2]) : size - 1, size - 1) : size - 1;
    res.writeHead(range ? 206 : 200, {'Content-Type': type, 'Content-Length': end - start + 1, 'Accept-Ranges': 'bytes',
      ...(range ? {'Content-Range': `bytes ${start}-${end}/${size}`} : {})});
    fs.createReadStream(file, {start, end}).pipe(res);
  });
  return new Promise(resolve => server.listen(0, '127.0.0.1', () => resolve({server, port: server.address().port})));
}

// The watchdog under ctest's TIMEOUT 150, so the children are killed.
await runE2E({name: 'hostile_text', timeoutMs: 140000}, async ({checks, defer, work, seamap, sourceDir, seeder,
  launchBrowser, start, shot}) => {
  const survey = path.join(work, 'survey');
  const map = path.join(work, 'map.mbtiles');
  await run(seamap, ['simulate', '--out', survey, '--frames', '12', '--line-length', '2', '--seed', '3', '--quiet']);
  // The last photo (drawn on top of the others) gets a file name that is markup.
  const photoName = `${payload('photo')}.png`;
  fs.renameSync(path.join(survey, 'photo', 'frame_000011.png'), path.join(survey, 'photo', photoName));
  const nav = path.join(survey, 'nav.csv');
  fs.writeFileSync(nav, fs.readFileSync(nav, 'utf8').replace(/^frame_000011\.png/m, photoName));
  const config = path.join(work, 'config.json');
  fs.writeFileSync(config, JSON.stringify({name: payload('name'), attribution: payload('attribution')}));
  await run(seamap, ['build', '--images', path.join(survey, 'photo'), '--nav', nav, '--camera',
    path.join(survey, 'camera.json'), '--origin', '43.1,131.9', '--config', config, '--quiet', '--out', map]);
  await run(seeder, [map]);  // five recogniser detections, then their texts made markup
  const texts = {class: payload('class'), model: payload('model'), source: payload('source'),
    status: payload('status'), note: payload('note'), layer: payload('layer')};
  await run('sqlite3', [map, `UPDATE detections SET class = ${sqlText(texts.class)}, model = ${sqlText(texts.model)},
    source = ${sqlText(texts.source)}, status = ${sqlText(texts.status)}, note = ${sqlText(texts.note)};
    UPDATE metadata SET value = ${sqlText(`raw,${texts.layer}`)} WHERE name = 'seamap_layers';`]);
  const folder = path.join(work, 'missions');
  fs.mkdirSync(folder);
  fs.copyFileSync(map, path.join(folder, 'dive_a.mbtiles'));
  const fileName = `${payload('file')}.mbtiles`;
  fs.copyFileSync(map, path.join(folder, fileName));

  const server = start(seamap, ['serve', map, '--host', '127.0.0.1', '--port', '0', '--web', path.join(sourceDir, 'web')]);
  await waitForOutput(server, /serving http:\/\/127\.0\.0\.1:\d+\//, 20000);
  const base = /serving (http:\/\/127\.0\.0\.1:\d+\/)/.exec(server.output)[1];
  // An operator mark whose class and note are markup, through the API as a client would send it.
  const mark = await fetch(new URL('api/detections', base), {method: 'POST', headers: {'Content-Type': 'application/json'},
    body: JSON.stringify({type: 'Feature', geometry: {type: 'Point', coordinates: [131.9000003, 43.10000472]},
      properties: {class: payload('mark'), note: payload('mark-note')}})});
  if (mark.status !== 201) throw new Error(`mark refused: ${mark.status} ${await mark.text()}`);
  checks.ok('a mission with markup in every text it holds', 'attribution, name, layer, photo, detections, a mark');

  const browser = await launchBrowser();
  const page = await browser.newPage({viewport: {width: 1100, height: 700}});
  page.setDefaultTimeout(15000);
  const errors = [];
  page.on('pageerror', e => errors.push(e.message));
  // Did a payload run? An <img onerror> fires once the request for `x` failed: let the network settle first.
  const ran = async () => {
    await page.waitForLoadState('networkidle').catch(() => {});
    await sleep(300);
    return page.evaluate(() => window.__pwned);
  };
  const noScript = async what => {
    const where = await ran();
    if (where !== undefined) throw new Error(`the payload in the ${where} ran (${what})`);
  };
  const textOf = selector => page.$eval(selector, e => e.textContent);
  const literal = (shown, text, what) => {
    if (!String(shown).includes(text)) throw new Error(`${what} not shown as typed: "${String(shown).slice(0, 160)}"`);
  };

  await checks.run('console: the attribution and the layer names load as text', async () => {
    await page.goto(base);
    await page.waitForSelector('body[data-ready="true"]');
    await noScript('on load');
    literal(await textOf('.leaflet-control-attribution'), payload('attribution'), 'the attribution');
    literal(await textOf('.leaflet-control-layers'), texts.layer, 'the layer name');
    if (await page.$('.leaflet-control-attribution img, .leaflet-control-layers img')) throw new Error('an <img> was made');
    return 'attribution and layer control';
  });

  // A point of the last photo's footprint that no other photo covers (its northern edge).
  const frame = await (await fetch(new URL('api/frames/11', base))).json();
  if (frame.image !== photoName) throw new Error(`frame 11 is "${frame.image}"`);
  const corners = frame.footprint;
  const centre = corners.reduce(([x, y], [lon, lat]) => [x + lon / corners.length, y + lat / corners.length], [0, 0]);
  const north = [...corners].sort((a, b) => b[1] - a[1]).slice(0, 2);
  const edge = [(north[0][0] + north[1][0]) / 2, (north[0][1] + north[1][1]) / 2];
  const inside = [centre[0] + 0.85 * (edge[0] - centre[0]), centre[1] + 0.85 * (edge[1] - centre[1])];
  const screenPoint = () => page.evaluate(([lon, lat]) => {
    const p = window.seamap.map.latLngToContainerPoint([lat, lon]);
    const box = window.seamap.map.getContainer().getBoundingClientRect();
    return {x: box.left + p.x, y: box.top + p.y};
  }, inside);

  await checks.run('console: hovering the photo\'s footprint shows its file name as text', async () => {
    await page.check('#footprints');
    await page.waitForFunction(() => Number(document.querySelector('#footprints').dataset.count) === 12);
    const {x, y} = await screenPoint();
    await page.mouse.move(x - 3, y);
    await page.mouse.move(x, y, {steps: 3});
    const tooltip = await page.waitForSelector('.leaflet-tooltip', {timeout: 5000});
    const text = await tooltip.textContent();
    await noScript('hovering the footprint');
    if (text !== photoName) throw new Error(`tooltip "${text}"`);
    await shot(page, 'hostile-footprint-tooltip');
    return `tooltip "${text.slice(0, 40)}…"`;
  });

  await checks.run('console: the photo viewer and the photo list show the file name as text', async () => {
    const {x, y} = await screenPoint();
    await page.mouse.click(x, y);  // on the footprint: the photo viewer
    await page.waitForSelector('#photo-viewer:not([hidden])');
    literal(await textOf('#photo-caption'), photoName, 'the caption');
    await noScript('the photo viewer');
    await page.click('#photo-viewer-close');
    await page.uncheck('#footprints');
    await page.mouse.click(x, y);  // on the map: the photos covering the spot
    await page.waitForFunction(() => document.querySelectorAll('#photos li').length > 0);
    literal(await textOf('#photos'), photoName, 'the photo list');
    await noScript('the photo list');
    return 'caption and list';
  });

  await checks.run('console: detection and mark popups, list and legend show their texts as text', async () => {
    await page.waitForFunction(() => document.querySelectorAll('.leaflet-marker-icon[data-detection-id]').length >= 6);
    const ids = await page.$$eval('.leaflet-marker-icon[data-detection-id]', els => els.map(e => e.dataset.detectionId));
    for (const id of ids) {
      await page.evaluate(key => window.seamap.detections.focus(key), id);
      await page.waitForSelector(`.leaflet-popup .detection-popup[data-id="${id}"]`);
      const popup = await textOf(`.leaflet-popup .detection-popup[data-id="${id}"]`);  // not one fading out
      const isMark = popup.includes('operator mark');
      // (source and status are read back as one of their known values: not shown as stored)
      for (const text of isMark ? [payload('mark'), payload('mark-note')] : [texts.class, texts.model, texts.note]) {
        literal(popup, text, `popup of ${id}`);
      }
      if (await page.$('.leaflet-popup img:not(.thumb)')) throw new Error(`an <img> in the popup of ${id}`);
      await noScript(`the popup of detection ${id}`);
      await page.evaluate(() => window.seamap.map.closePopup());
    }
    literal(await textOf('#detection-list'), texts.class, 'the detection list');
    literal(await textOf('.class-legend'), texts.class, 'the class legend');
    await noScript('the list and the legend');
    await shot(page, 'hostile-detections');
    return `${ids.length} popups`;
  });
  await stopProcess(server);

  const catalogue = start(seamap, ['serve', folder, '--host', '127.0.0.1', '--port', '0', '--web', path.join(sourceDir, 'web')]);
  await waitForOutput(catalogue, /serving http:\/\/127\.0\.0\.1:\d+\//, 20000);
  const catalogueBase = /serving (http:\/\/127\.0\.0\.1:\d+\/)/.exec(catalogue.output)[1];
  await checks.run('catalogue: file and mission names, the chosen map\'s attribution as text', async () => {
    await page.goto(catalogueBase);
    await page.waitForSelector('body[data-ready="true"]');
    const listed = await textOf('#missions');
    literal(listed, fileName, 'the file name');
    literal(listed, payload('name'), 'the mission name');
    await page.click('#missions li[data-id="dive_a"]');
    await page.waitForSelector('body[data-mission="dive_a"]');
    literal(await textOf('.leaflet-control-attribution'), payload('attribution'), 'the attribution');
    await noScript('the catalogue');
    const ids = await page.$$eval('#missions li', lis => lis.map(li => li.dataset.id));
    const other = ids.find(id => id !== 'dive_a');
    await page.click(`#missions li[data-id="${other}"]`);
    await page.waitForSelector(`body[data-mission="${other}"]`);
    await noScript('the catalogue, the mission with the hostile file name');
    await page.goto(new URL(`missions/${other}/`, catalogueBase).href);
    await page.waitForSelector('body[data-ready="true"]');
    literal(await textOf('.leaflet-control-attribution'), payload('attribution'), 'the attribution in the console');
    await noScript('the console of the mission with the hostile file name');
    return `missions ${ids.join(', ')}`;
  });

  const site = path.join(work, 'site');
  fs.mkdirSync(path.join(site, 'js'), {recursive: true});
  await run(seamap, ['export', map, path.join(site, 'mission.pmtiles'), '--quiet']);
  fs.copyFileSync(path.join(sourceDir, 'web', 'pmtiles.html'), path.join(site, 'pmtiles.html'));
  fs.cpSync(path.join(sourceDir, 'web', 'vendor'), path.join(site, 'vendor'), {recursive: true});
  fs.copyFileSync(path.join(sourceDir, 'web', 'js', 'class_colour.js'), path.join(site, 'js', 'class_colour.js'));
  const host = await staticServer(site);
  defer(() => host.server.close());
  await checks.run('pmtiles.html: attribution, title and object popups as text', async () => {
    await page.goto(`http://127.0.0.1:${host.port}/pmtiles.html?url=mission.pmtiles`);
    await page.waitForSelector('#title[data-state="ready"]');
    literal(await textOf('.leaflet-control-attribution'), payload('attribution'), 'the attribution');
    literal(await textOf('#title'), payload('name'), 'the title');
    await noScript('pmtiles.html on load');
    const objects = await page.evaluate(() => window.seamapViewer.objects.getLayers().length);
    if (objects < 6) throw new Error(`${objects} objects`);
    const popups = [];
    for (let i = 0; i < objects; ++i) {
      // This object's own popup (the previous one may still be fading out).
      popups.push(await page.evaluate(index => {
        const layer = window.seamapViewer.objects.getLayers()[index];
        layer.openPopup();
        return layer.getPopup().getElement().querySelector('.leaflet-popup-content').textContent;
      }, i));
      await noScript(`pmtiles.html popup ${i}`);
    }
    const all = popups.join('\n');
    for (const text of [texts.class, texts.note, payload('mark'), payload('mark-note')]) {
      literal(all, text, 'a popup text');
    }
    await shot(page, 'hostile-pmtiles');
    return `${objects} popups`;
  });

  await checks.run('no script errors on the pages', async () => {
    if (errors.length) throw new Error(errors.join(' | '));
    return '';
  });
});
