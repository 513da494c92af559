// The console for a mission georeferenced by a towed GPS buoy (issue 18), in
// headless Chromium: `seamap serve MAP --buoy buoy.csv --georef-nav nav.csv`;
// the buoy's track beside the vehicle's, the keyframes used in the fit and
// those dropped as dots, all named in the legend and each hidden by it.
import path from 'node:path';
import {runE2E, run, waitFor, waitForOutput} from './harness.mjs';

await runE2E({name: 'georef', timeoutMs: 120000}, async ({checks, work, seamap, sourceDir, launchBrowser, start, shot}) => {
  const survey = path.join(work, 'survey');
  const buoy = path.join(work, 'buoy');
  const map = path.join(work, 'map.mbtiles');
  const nav = path.join(work, 'nav.csv');
  await run(seamap, ['simulate', '--out', survey, '--frames', '12', '--line-length', '2', '--seed', '3', '--quiet']);
  await run(seamap, ['build', '--images', path.join(survey, 'photo'), '--nav', path.join(survey, 'nav.csv'),
    '--camera', path.join(survey, 'camera.json'), '--origin', '43.1,131.9', '--quiet', '--out', map]);
  await run(seamap, ['simulate-buoy', '--out', buoy, '--origin', '43.1,131.9', '--lines', '2', '--line-length', '120']);
  await run(seamap, ['georef', '--keyframes', path.join(buoy, 'keyframes.txt'), '--buoy', path.join(buoy, 'buoy.csv'),
    '--tether-length', '30', '--depth-csv', path.join(buoy, 'depth.csv'), '--out', nav]);
  const server = start(seamap, ['serve', map, '--host', '127.0.0.1', '--port', '0', '--web', path.join(sourceDir, 'web'),
    '--buoy', path.join(buoy, 'buoy.csv'), '--georef-nav', nav]);
  await waitForOutput(server, /serving http:\/\/127\.0\.0\.1:\d+\//, 20000);
  const base = /serving (http:\/\/127\.0\.0\.1:\d+\/)/.exec(server.output)[1];
  const api = async p => (await fetch(new URL(p, base))).json();
  const buoyTrack = await api('api/track?source=buoy');
  const keyframes = (await api('api/keyframes')).features;
  const good = keyframes.filter(f => f.properties.good).length;

  const browser = await launchBrowser();
  const page = await browser.newPage({viewport: {width: 1100, height: 700}});
  page.setDefaultTimeout(10000);
  const errors = [];
  page.on('pageerror', e => errors.push(e.message));
  await page.goto(base);
  await page.waitForSelector('body[data-ready="true"]');
  const drawn = () => page.evaluate(() => ({
    buoy: document.querySelectorAll('path.track-buoy').length ? window.seamap.tracks.buoy.points.length : 0,
    good: document.querySelectorAll('path.keyframe-good').length,
    dropped: document.querySelectorAll('path.keyframe-dropped').length,
    sigma: document.querySelectorAll('path.keyframe-sigma').length,
  }));

  await checks.run('the buoy track is drawn beside the vehicle\'s, every fix', async () => {
    const n = await waitFor('the buoy line', async () => (await drawn()).buoy || null);
    if (n !== buoyTrack.geometry.coordinates.length) throw new Error(`${n} points drawn, ${buoyTrack.geometry.coordinates.length} fixes`);
    const stroke = await page.$eval('path.track-buoy', p => p.getAttribute('stroke'));
    const vehicle = await page.$eval('path.track-estimated', p => p.getAttribute('stroke'));
    if (stroke === vehicle) throw new Error('buoy and vehicle share a colour');
    return `${n} fixes, ${stroke} beside ${vehicle}`;
  });

  await checks.run('keyframes marked: used in the fit and dropped, as the API says', async () => {
    const d = await waitFor('the keyframe dots', async () => { const x = await drawn(); return x.good ? x : null; });
    if (d.good !== good || d.dropped !== keyframes.length - good) {
      throw new Error(`${d.good} used and ${d.dropped} dropped drawn; the API has ${good} and ${keyframes.length - good}`);
    }
    if (!(good > 0 && good < keyframes.length)) throw new Error(`a test survey with ${good} of ${keyframes.length} used says nothing`);
    await page.evaluate(() => {
      const {map, tracks} = window.seamap;
      map.fitBounds(tracks.buoy.line.getBounds(), {padding: [20, 20], animate: false});
    });
    await shot(page, 'console-georef');
    return `${d.good} used, ${d.dropped} dropped`;
  });

  await checks.run('each keyframe\'s predicted error drawn around it, to scale', async () => {
    const withSigma = keyframes.filter(f => f.properties.sigma_m > 0);
    if (withSigma.length !== keyframes.length) throw new Error(`${withSigma.length} of ${keyframes.length} keyframes have sigma_m`);
    const d = await drawn();
    if (d.sigma !== withSigma.length) throw new Error(`${d.sigma} circles drawn for ${withSigma.length} keyframes`);
    // Zoomed in on one keyframe, its circle's radius in pixels is 1.73 sigma_m in metres at the map's scale.
    const k = withSigma[Math.floor(withSigma.length / 2)];
    const [lon, lat] = k.geometry.coordinates;
    const measured = await page.evaluate(([lat, lon, sigma]) => {
      const {map} = window.seamap;
      map.setView([lat, lon], 22, {animate: false});
      const centre = map.latLngToContainerPoint([lat, lon]);
      const east = map.latLngToContainerPoint([lat, lon + 1e-5]);
      const metresPerDegree = 111320 * Math.cos(lat * Math.PI / 180);
      const pixelsPerMetre = (east.x - centre.x) / (1e-5 * metresPerDegree);
      let best = null;
      map.eachLayer(l => {
        if (!(l instanceof window.L.Circle)) return;
        const c = l.getLatLng();
        if (Math.abs(c.lat - lat) < 1e-9 && Math.abs(c.lng - lon) < 1e-9) best = l;
      });
      const result = best && {radiusPx: best._radius, expectedPx: 1.73 * sigma * pixelsPerMetre};
      map.fitBounds(window.seamap.tracks.buoy.line.getBounds(), {padding: [20, 20], animate: false});
      return result;
    }, [lat, lon, k.properties.sigma_m]);
    if (!measured) throw new Error('no circle around the keyframe');
    if (Math.abs(measured.radiusPx / measured.expectedPx - 1) > 0.05) {
      throw new Error(`radius ${measured.radiusPx.toFixed(1)} px, expected ${measured.expectedPx.toFixed(1)} px`);
    }
    return `${d.sigma} circles; sigma_m ${k.properties.sigma_m} m drawn ${measured.radiusPx.toFixed(1)} px at zoom 22`;
  });

  await checks.run('the legend names each and hides each', async () => {
    const legend = (await page.textContent('.track-legend')).replace(/\s+/g, ' ');
    for (const words of ['vehicle', 'GPS buoy', 'used in the fit', 'dropped']) {
      if (!legend.includes(words)) throw new Error(`legend "${legend}" lacks "${words}"`);
    }
    await page.uncheck('.track-legend [data-track="buoy"] input');
    await page.uncheck('.track-legend [data-track="keyframes-good"] input');
    const hidden = await drawn();
    if (hidden.buoy || hidden.good || !hidden.dropped) throw new Error(`after hiding: ${JSON.stringify(hidden)}`);
    await page.check('.track-legend [data-track="buoy"] input');
    await page.check('.track-legend [data-track="keyframes-good"] input');
    const shown = await drawn();
    if (!shown.buoy || shown.good !== good) throw new Error(`after showing again: ${JSON.stringify(shown)}`);
    return `"${legend.trim()}"`;
  });

  await checks.run('no script errors on the page', async () => {
    if (errors.length) throw new Error(errors.join('; '));
    return 'none';
  });
});
