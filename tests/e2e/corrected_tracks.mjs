// The console's browser test, second part: a mission whose trajectory was
// corrected. tests/tools/corrected_mission builds a simulated survey with
// navigation errors, each frame placed at its true pose and the navigation's
// kept beside it, slowly, while `seamap serve` follows the growing file; the
// console must draw both tracks in two colours with a legend, grow both live,
// and keep the vehicle at the estimated pose.

import fs from 'node:fs';
import path from 'node:path';
import {freePort, run, sleep, startProcess, stopProcess, waitFor, waitForOutput} from './harness.mjs';

const FRAMES = 48;
const PACE_MS = 250;   // the mission grows for about 12 s; `seamap serve` looks every 2 s

// Polyline colours and point counts of the two tracks as the page shows them.
function trackLines() {
  const {tracks} = window.seamap;
  const line = (selector, track) => {
    const element = document.querySelector(selector);
    return {drawn: Boolean(element), stroke: element && element.getAttribute('stroke'), points: track ? track.points.length : 0};
  };
  return {estimated: line('path.track-estimated', tracks.estimated), nav: line('path.track-nav', tracks.nav)};
}

export async function checkCorrectedTracks({browser, checks, seamap, tool, work, sourceDir, shot}) {
  if (!fs.existsSync(tool)) {
    checks.fail('corrected trajectory: the test tool exists', new Error(`no ${tool} (build target corrected_mission)`));
    return;
  }
  const survey = path.join(work, 'corrected-survey');
  await run(seamap, ['simulate', '--out', survey, '--frames', String(FRAMES), '--line-length', '4', '--seed', '7',
    '--nav-noise', '0.03', '--nav-drift', '6', '--heading-noise', '1', '--quiet']);
  const mission = path.join(work, 'out', 'corrected.mbtiles');
  const builder = startProcess(tool, [survey, mission, '--pace-ms', String(PACE_MS)]);
  let server = null;
  const page = await browser.newPage({viewport: {width: 1280, height: 800}});
  page.setDefaultTimeout(10000);
  const pageErrors = [];
  page.on('pageerror', error => pageErrors.push(error.message));
  try {
    await waitFor('the corrected mission file', () => fs.existsSync(mission), {timeoutMs: 20000, intervalMs: 100});
    const port = await freePort();
    server = startProcess(seamap, ['serve', mission, '--port', String(port), '--read-only', '--web', path.join(sourceDir, 'web')]);
    await waitForOutput(server, new RegExp(`serving http://127\\.0\\.0\\.1:${port}/`), 20000);
    const base = `http://127.0.0.1:${port}/`;
    await page.goto(base, {waitUntil: 'domcontentloaded'});
    await page.waitForSelector('body[data-ready="true"]', {timeout: 20000});

    await checks.run('corrected trajectory: both tracks grow while the mission grows', async () => {
      const first = await waitFor('the navigation track', async () => {
        const lines = await page.evaluate(trackLines);
        return lines.nav.points >= 2 ? lines : null;
      }, {timeoutMs: 20000});
      if (builder.exitCode !== null) throw new Error('the mission was finished before the browser watched it');
      const later = await waitFor('both tracks to grow', async () => {
        const lines = await page.evaluate(trackLines);
        return lines.nav.points > first.nav.points && lines.estimated.points > first.estimated.points ? lines : null;
      }, {timeoutMs: 20000});
      return `estimated ${first.estimated.points} -> ${later.estimated.points}, nav ${first.nav.points} -> ${later.nav.points} points`;
    });

    const done = await builder.exited;
    if (done.code !== 0) throw new Error(`corrected_mission failed (${done.signal || done.code}): ${builder.output.slice(-1500)}`);
    await waitFor('the mission complete in the console', () => page.$eval('#progress', el => el.dataset.state === 'complete'), {timeoutMs: 15000});
    await sleep(500);

    await checks.run('corrected trajectory: the API serves two different tracks', async () => {
      const get = async source => (await fetch(new URL(`api/track?source=${source}`, base))).json();
      const [nav, estimated] = await Promise.all([get('nav'), get('estimated')]);
      if (!nav.properties.corrected || !estimated.properties.corrected) throw new Error('properties.corrected is not true');
      const a = nav.geometry.coordinates, b = estimated.geometry.coordinates;
      if (a.length !== b.length || a.length < FRAMES / 2) throw new Error(`${a.length} nav and ${b.length} estimated points`);
      const metres = (p, q) => Math.hypot((p[0] - q[0]) * 111320 * Math.cos(p[1] * Math.PI / 180), (p[1] - q[1]) * 110540);
      const largest = Math.max(...a.map((p, i) => metres(p, b[i])));
      if (!(largest > 0.05)) throw new Error(`the tracks differ by at most ${largest.toFixed(3)} m`);
      const status = await (await fetch(new URL('api/status', base))).json();
      if (!status.trajectory_corrected) throw new Error('/api/status does not say trajectory_corrected');
      return `${a.length} points each, up to ${largest.toFixed(2)} m apart; ${status.corrected_frames} corrected frames`;
    });

    await checks.run('corrected trajectory: two polylines in two colours and a legend naming both', async () => {
      const lines = await page.evaluate(trackLines);
      if (!lines.estimated.drawn || !lines.nav.drawn) throw new Error(`drawn: ${JSON.stringify(lines)}`);
      if (!lines.estimated.stroke || lines.estimated.stroke === lines.nav.stroke) {
        throw new Error(`colours ${lines.estimated.stroke} and ${lines.nav.stroke}`);
      }
      const legend = (await page.textContent('.track-legend')) || '';
      if (!/navigation/.test(legend) || !/estimated/.test(legend)) throw new Error(`legend says "${legend}"`);
      return `estimated ${lines.estimated.stroke}, navigation ${lines.nav.stroke}; legend "${legend.trim()}"`;
    });

    await checks.run('corrected trajectory: a console opened on the finished mission draws both at once', async () => {
      // Also a fresh view of the tiles: `seamap serve` sends no tile events for
      // a map another process writes, so tiles fetched while it grew are stale.
      await page.reload({waitUntil: 'domcontentloaded'});
      await page.waitForSelector('body[data-ready="true"]', {timeout: 20000});
      const lines = await waitFor('both tracks', async () => {
        const l = await page.evaluate(trackLines);
        return l.nav.drawn && l.estimated.drawn && l.nav.points === FRAMES ? l : null;
      }, {timeoutMs: 10000});
      await page.evaluate(() => {
        const {map, tracks} = window.seamap;
        map.fitBounds(tracks.nav.line.getBounds().extend(tracks.estimated.line.getBounds()), {padding: [30, 30], animate: false});
      });
      await waitFor('the tiles in view', () => page.evaluate(() => !window.seamap.layers.main.isLoading()), {timeoutMs: 10000});
      await sleep(300);
      await shot(page, 'console-corrected');
      return `${lines.estimated.points} and ${lines.nav.points} points`;
    });

    await checks.run('corrected trajectory: the vehicle is at the estimated pose', async () => {
      const status = await (await fetch(new URL('api/status', base))).json();
      const frame = await (await fetch(new URL(`api/frames/${status.last_pose.frame}`, base))).json();
      const marker = await page.evaluate(() => window.seamap.vehicle.marker.getLatLng());
      if (!frame.nav) throw new Error(`frame ${frame.id} has no nav pose`);
      const near = (lat, lon) => Math.abs(marker.lat - lat) < 1e-9 && Math.abs(marker.lng - lon) < 1e-9;
      if (!near(frame.lat, frame.lon)) throw new Error(`marker at ${marker.lat},${marker.lng}, frame placed at ${frame.lat},${frame.lon}`);
      if (near(frame.nav.lat, frame.nav.lon)) throw new Error('marker at the navigation pose');
      return `frame ${frame.id}`;
    });

    await checks.run('corrected trajectory: the legend hides and shows the navigation track', async () => {
      await page.uncheck('.track-legend [data-track="nav"] input');
      if (await page.$('path.track-nav')) throw new Error('still drawn after unchecking');
      await page.check('.track-legend [data-track="nav"] input');
      await page.waitForSelector('path.track-nav', {state: 'attached', timeout: 3000});
      return 'ok';
    });

    await checks.run('corrected trajectory: no script errors on the page', async () => {
      if (pageErrors.length) throw new Error(pageErrors.join(' | '));
      return '';
    });
  } catch (error) {
    checks.fail('corrected trajectory', error);
    if (server) console.log(`# serve output:\n${server.output.slice(-2000).replace(/^/gm, '# ')}`);
    console.log(`# corrected_mission output:\n${builder.output.slice(-2000).replace(/^/gm, '# ')}`);
  } finally {
    await page.close().catch(() => {});
    await stopProcess(builder);
    await stopProcess(server);
  }
}
