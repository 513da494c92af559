// A mission published with no SeaMap server: `seamap export` writes a
// .pmtiles archive, a plain static file server (byte ranges, nothing else)
// serves it with web/pmtiles.html, and headless Chromium shows the map with the
// dive's track and objects. Every tile the page's PMTiles reader fetches must
// equal the map's own tile.
import fs from 'node:fs';
import http from 'node:http';
import path from 'node:path';
import {runE2E, run} from './harness.mjs';

const TYPES = {'.html': 'text/html', '.js': 'text/javascript', '.css': 'text/css', '.png': 'image/png'};

// Any static host: files, HEAD, single byte ranges (RFC 7233), 404s. Counts requests.
function staticServer(root) {
  const stats = {ranges: 0, requests: [], notFound: []};
  const server = http.createServer((req, res) => {
    const url = new URL(req.url, 'http://x');
    const file = path.join(root, decodeURIComponent(url.pathname));
    stats.requests.push(url.pathname);
    if (!file.startsWith(root) || !fs.existsSync(file) || !fs.statSync(file).isFile()) {
      stats.notFound.push(url.pathname);
      res.writeHead(404).end();
      return;
    }
    const size = fs.statSync(file).size;
    const type = TYPES[path.extname(file)] || 'application/octet-stream';
    const range = /^bytes=(\d+)-(\d*)$/.exec(req.headers.range || '');
    if (range) {
      stats.ranges++;
      const start = Number(range[1]);
      const end = Math.min(range[2] ? Number(range[2]) : size - 1, size - 1);
      res.writeHead(206, {'Content-Type': type, 'Content-Length': end - start + 1,
        'Content-Range': `bytes ${start}-${end}/${size}`, 'Accept-Ranges': 'bytes'});
      if (req.method === 'HEAD') return res.end();
      fs.createReadStream(file, {start, end}).pipe(res);
      return;
    }
    res.writeHead(200, {'Content-Type': type, 'Content-Length': size, 'Accept-Ranges': 'bytes'});
    if (req.method === 'HEAD') return res.end();
    fs.createReadStream(file).pipe(res);
  });
  return new Promise(resolve => server.listen(0, '127.0.0.1', () => resolve({server, stats, port: server.address().port})));
}

function tilesOf(folder) {
  const tiles = [];
  for (const z of fs.readdirSync(folder).filter(n => /^\d+$/.test(n)))
    for (const x of fs.readdirSync(path.join(folder, z)))
      for (const f of fs.readdirSync(path.join(folder, z, x)))
        tiles.push({z: +z, x: +x, y: +f.split('.')[0], file: path.join(folder, z, x, f)});
  return tiles;
}

await runE2E({name: 'pmtiles', timeoutMs: 120000}, async ({checks, defer, work, seamap, sourceDir, launchBrowser, shot}) => {
  const survey = path.join(work, 'survey');
  const map = path.join(work, 'map.mbtiles');
  const folder = path.join(work, 'folder');
  const root = path.join(work, 'site');
  await run(seamap, ['simulate', '--out', survey, '--frames', '12', '--line-length', '2', '--seed', '3', '--quiet']);
  await run(seamap, ['build', '--images', path.join(survey, 'photo'), '--nav', path.join(survey, 'nav.csv'),
    '--camera', path.join(survey, 'camera.json'), '--origin', '43.1,131.9', '--quiet', '--out', map,
    '--detect', '--detect-model', path.join(sourceDir, 'tests', 'fixtures', 'yolo_v8_fixture.onnx')]);
  await run(seamap, ['export', map, folder, '--quiet']);  // the map's tiles as files: the reference bytes
  fs.mkdirSync(root);
  await run(seamap, ['export', map, path.join(root, 'mission.pmtiles'), '--quiet']);
  fs.copyFileSync(path.join(sourceDir, 'web', 'pmtiles.html'), path.join(root, 'pmtiles.html'));
  fs.cpSync(path.join(sourceDir, 'web', 'vendor'), path.join(root, 'vendor'), {recursive: true});
  fs.mkdirSync(path.join(root, 'js'));
  fs.copyFileSync(path.join(sourceDir, 'web', 'js', 'class_colour.js'), path.join(root, 'js', 'class_colour.js'));
  if (!fs.existsSync(path.join(root, 'vendor', 'pmtiles', 'pmtiles.js'))) {
    throw new Error('web/vendor/pmtiles is missing: run scripts/setup_web.sh');
  }
  const site = await staticServer(root);
  defer(() => site.server.close());
  checks.ok('mission exported and served by a plain static server', `port ${site.port}`);

  const browser = await launchBrowser();
  const page = await browser.newPage({viewport: {width: 1024, height: 700}});
  page.setDefaultTimeout(15000);
  const errors = [];
  page.on('pageerror', e => errors.push(e.message));
  page.on('console', m => m.type() === 'error' && errors.push(m.text()));
  const base = `http://127.0.0.1:${site.port}`;

  await checks.run('the viewer opens the archive and shows its tiles', async () => {
    await page.goto(`${base}/pmtiles.html?url=mission.pmtiles`);
    await page.waitForSelector('#title[data-state="ready"]');
    await page.waitForFunction(() => document.querySelectorAll('.leaflet-tile-loaded').length > 0);
    await page.waitForFunction(() => [...document.querySelectorAll('img.leaflet-tile')]
      .every(img => img.complete), null, {timeout: 15000});
    // Tiles the archive lacks (off the survey) are hidden by the reader; the others are images.
    const sizes = await page.$$eval('img.leaflet-tile-loaded',
      imgs => imgs.filter(i => i.style.display !== 'none').map(i => i.naturalWidth));
    if (!sizes.length || sizes.some(w => w !== 256)) throw new Error(`tile widths ${sizes}`);
    await shot(page, 'pmtiles-viewer');
    return `${sizes.length} tiles drawn, title "${await page.textContent('#title')}"`;
  });

  await checks.run('the dive\'s track and objects are drawn from the archive', async () => {
    const drawn = await page.evaluate(() => {
      const {track, objects, metadata} = window.seamapViewer;
      return {line: track ? track.getLayers()[0].getLatLngs().length : 0, points: metadata.seamap_track?.properties.points,
        objects: objects.getLayers().length, classes: objects.getLayers().map(l => l.feature.properties.class),
        paths: document.querySelectorAll('path.track').length, circles: document.querySelectorAll('path.object').length};
    });
    if (!drawn.line || drawn.line !== drawn.points || drawn.paths !== 1) throw new Error(JSON.stringify(drawn));
    if (!drawn.objects || drawn.circles !== drawn.objects) throw new Error(JSON.stringify(drawn));
    await page.click('path.object');
    const popup = await page.textContent('.leaflet-popup-content');
    if (!popup.includes(drawn.classes[0]) || !popup.includes('score')) throw new Error(popup);
    return `${drawn.line} track points, ${drawn.objects} objects (${[...new Set(drawn.classes)].join(', ')}); popup "${popup.slice(0, 60)}"`;
  });

  await checks.run('every tile read over HTTP ranges equals the map\'s tile', async () => {
    const tiles = tilesOf(folder);
    if (tiles.length < 5) throw new Error(`only ${tiles.length} tiles exported`);
    const got = await page.evaluate(async ids => {
      const out = [];
      for (const {z, x, y} of ids) {
        const t = await window.seamapViewer.archive.getZxy(z, x, y);
        out.push(t ? btoa(String.fromCharCode(...new Uint8Array(t.data))) : null);
      }
      return out;
    }, tiles.map(({z, x, y}) => ({z, x, y})));
    const wrong = tiles.filter((t, i) => got[i] !== fs.readFileSync(t.file).toString('base64'));
    if (wrong.length) throw new Error(`${wrong.length} of ${tiles.length} differ, e.g. ${wrong[0].z}/${wrong[0].x}/${wrong[0].y}`);
    if (site.stats.ranges < 2) throw new Error(`only ${site.stats.ranges} range requests`);
    const other = site.stats.requests.filter(p => !/^\/(pmtiles\.html|mission\.pmtiles|vendor\/|js\/class_colour\.js$)/.test(p));
    if (other.length) throw new Error(`requests beyond the static files: ${other.join(' ')}`);
    return `${tiles.length} tiles, ${site.stats.ranges} range requests`;
  });

  await checks.run('a missing archive is named on the page', async () => {
    await page.goto(`${base}/pmtiles.html?url=gone.pmtiles`);
    await page.waitForSelector('#title[data-state="error"]');
    const text = await page.textContent('#title');
    if (!text.includes('gone.pmtiles')) throw new Error(text);
    return text;
  });

  await checks.run('no script errors on the page', async () => {
    const real = errors.filter(e => !/Failed to load resource|gone\.pmtiles/.test(e));
    if (real.length) throw new Error(real.join(' | '));
    return '';
  });
});
