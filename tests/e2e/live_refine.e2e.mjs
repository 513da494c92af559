// replay --refine-nav in headless Chromium (issue 30): while a drifting
// survey is replayed, the refinement on the worker corrects the trajectory
// as the vehicle crosses its first line; the console then draws the track
// again at the corrected poses (apart from the navigation's) and the tiles
// painted again reach the page with new versions.
import path from 'node:path';
import {runE2E, run, waitFor, waitForOutput} from './harness.mjs';

await runE2E({name: 'live_refine', timeoutMs: 150000}, async ({checks, work, seamap, sourceDir, launchBrowser, start, shot}) => {
  const survey = path.join(work, 'survey');
  const map = path.join(work, 'live.mbtiles');
  // Three 3 m lines 0.9 m apart, the navigation drifting 1 m/min: the second line crosses the first after ~10 s.
  await run(seamap, ['simulate', '--out', survey, '--frames', '72', '--line-length', '3', '--line-spacing', '0.9',
    '--nav-drift', '1', '--nav-noise', '0.005', '--heading-noise', '0.5', '--image-format', 'jpg', '--seed', '5',
    '--quiet']);
  // The browser first: started while the replay runs (seconds on a loaded
  // machine), the page heard only the last seconds before the correction,
  // when every tile it heard was still being painted by the builder.
  const browser = await launchBrowser();
  const page = await browser.newPage({viewport: {width: 1000, height: 700}});
  page.setDefaultTimeout(10000);
  const errors = [];
  page.on('pageerror', e => errors.push(e.message));
  const replay = start(seamap, ['replay', survey, '--refine-nav', '--nav-noise', '0.005', '--nav-drift', '1',
    '--heading-noise', '0.5', '--speed', '1', '--out', map, '--host', '127.0.0.1', '--port', '0', '--quiet',
    '--web', path.join(sourceDir, 'web')]);
  await waitForOutput(replay, /serving http:\/\/127\.0\.0\.1:\d+\//, 30000);
  const base = /serving (http:\/\/127\.0\.0\.1:\d+\/)/.exec(replay.output)[1];
  await page.goto(base);
  await page.waitForSelector('body[data-ready="true"]', {timeout: 20000});
  // Every tile and trajectory event the page hears, with when it heard it.
  await page.evaluate(() => {
    const heard = window.heard = {tiles: [], corrections: []};
    window.seamap.live.on('tile', e => heard.tiles.push({...e, at: performance.now()}));
    window.seamap.live.on('trajectory', e => heard.corrections.push({...e, at: performance.now()}));
  });

  let correction = null;
  await checks.run('a correction arrives while the replay runs', async () => {
    correction = await waitFor('a trajectory event before the end of the dive', () => page.evaluate(() =>
      window.heard.corrections.find(c => !c.final) || null), {timeoutMs: 60000});
    if (/replay complete/.test(replay.output)) throw new Error('the replay had ended already');
    return `${correction.frames_corrected} frames corrected`;
  });

  await checks.run('the console draws the corrected track apart from the navigation', async () => {
    if (!correction) throw new Error('no correction');
    const apart = await waitFor('the track read again, off the navigation', () => page.evaluate(() => {
      const {tracks} = window.seamap;
      if (!tracks.reloads || !tracks.nav) return null;
      const est = tracks.estimated.points, nav = tracks.nav.points;
      let worst = 0;
      for (let i = 0; i < Math.min(est.length, nav.length); ++i) worst = Math.max(worst, est[i].distanceTo(nav[i]));
      return worst > 0.01 ? {worst, reloads: tracks.reloads, points: est.length} : null;
    }), {timeoutMs: 20000});
    return `${apart.reloads} reloads, ${apart.points} points, up to ${(apart.worst * 1000).toFixed(0)} mm from the navigation`;
  });

  await checks.run('tiles painted long before were painted again and refreshed', async () => {
    if (!correction) throw new Error('no correction');
    // Tiles announced again just before the correction whose last version was seconds older:
    // the builder had finished them; the repaint wrote them.
    const repainted = await page.evaluate(at => {
      const last = new Map(), again = [];
      for (const t of window.heard.tiles) {
        const k = `${t.layer}/${t.z}/${t.x}/${t.y}`;
        const before = last.get(k);
        if (before && t.at <= at && t.at > at - 3000 && before.at < t.at - 2000 && before.version !== t.version)
          again.push({z: t.z, x: t.x, y: t.y, version: t.version, was: before.version});
        last.set(k, t);
      }
      return again;
    }, correction.at);
    if (!repainted.length) throw new Error('no tile announced again with a new version before the correction');
    const t = repainted[0];
    const answer = await page.evaluate(async ({z, x, y}) => {
      const r = await fetch(`/tiles/${z}/${x}/${y}.png`);
      return {status: r.status, etag: r.headers.get('etag')};
    }, t);
    if (answer.status !== 200) throw new Error(`tile ${t.z}/${t.x}/${t.y}: HTTP ${answer.status}`);
    return `${repainted.length} tiles, e.g. ${t.z}/${t.x}/${t.y} ${t.was} -> ${t.version}`;
  });

  await checks.run('the dive ends refined and complete', async () => {
    await waitForOutput(replay, /refine live: \d+ solves/, 90000);
    const status = await page.evaluate(async () => (await fetch('/api/status')).json());
    if (status.state !== 'complete') throw new Error(`state ${status.state}`);
    const refined = await page.evaluate(async () => (await fetch('/api/track?source=refined')).status);
    if (refined !== 200) throw new Error(`/api/track?source=refined: HTTP ${refined}`);
    return /refine live: \d+ solves[^\n]*/.exec(replay.output)[0];
  });
  await shot(page, 'live_refine');
  if (errors.length) checks.fail('no page errors', new Error(errors.join('; ')));
});
