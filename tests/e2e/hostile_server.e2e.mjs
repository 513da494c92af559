// The console's side of /api/detections in pages (issue 33): a mission of
// 5003 detections answers 5000 and `next`; the console's getCollection
// (web/js/api.js, what the detections layer and the export load) follows it
// in a real Chromium and gets every one, once.
//
//   node tests/e2e/hostile_server.e2e.mjs
//
// Environment: SEAMAP_BIN, SEAMAP_SOURCE_DIR, SEAMAP_ARTIFACTS. Needs python3 (sqlite3) for the rows.
import path from 'node:path';
import {runE2E, run, waitForOutput} from './harness.mjs';

await runE2E({name: 'hostile_server', timeoutMs: 120000}, async ({checks, work, seamap, sourceDir, launchBrowser, start}) => {
  const survey = path.join(work, 'survey');
  const map = path.join(work, 'map.mbtiles');
  await run(seamap, ['simulate', '--out', survey, '--frames', '8', '--line-length', '2', '--seed', '7', '--quiet']);
  await run(seamap, ['build', '--images', path.join(survey, 'photo'), '--nav', path.join(survey, 'nav.csv'),
    '--camera', path.join(survey, 'camera.json'), '--origin', '43.1,131.9', '--quiet', '--out', map]);
  await run('python3', ['-c', `import sqlite3, sys
c = sqlite3.connect(sys.argv[1])
c.executemany("INSERT INTO detections (id, class, score, lat, lon, source, seq, status) VALUES (?, 'rock', 0.5, ?, 131.9, 'recogniser', ?, 'unconfirmed')",
              [(i, 43.1 + i * 1e-9, i) for i in range(1, 5004)])
c.commit()`, map]);
  const server = start(seamap, ['serve', map, '--host', '127.0.0.1', '--port', '0', '--web', path.join(sourceDir, 'web')]);
  await waitForOutput(server, /serving http:\/\/127\.0\.0\.1:\d+\//, 20000);
  const base = /serving (http:\/\/127\.0\.0\.1:\d+\/)/.exec(server.output)[1];

  await checks.run('the server answers 5000 detections and the next page', async () => {
    const first = await (await fetch(new URL('api/detections', base))).json();
    if (first.features.length !== 5000) throw new Error(`${first.features.length} features`);
    if (first.next !== '/api/detections?after=5000') throw new Error(`next ${first.next}`);
  });
  const browser = await launchBrowser();
  const page = await browser.newPage();
  page.setDefaultTimeout(20000);
  await checks.run('the console follows next and gets every detection once', async () => {
    await page.goto(new URL('tiles.json', base).href);  // a light page of the server's origin
    const got = await page.evaluate(async () => {
      const {getCollection} = await import('/js/api.js');
      const collection = await getCollection('/api/detections');
      return {count: collection.features.length, unique: new Set(collection.features.map(f => f.id)).size,
        next: collection.next ?? null, lastSeq: collection.last_seq};
    });
    if (got.count !== 5003 || got.unique !== 5003 || got.next !== null || got.lastSeq !== 5003)
      throw new Error(JSON.stringify(got));
  });
});
