// Swipe to compare (issue 21) in headless Chromium: a map built with a raw
// and an enhanced layer; the enhanced one is laid over the raw one and cut at
// a divider the operator drags; the cut follows the divider and the map's
// pans, and the live stream asks for both layers' tiles.
import fs from 'node:fs';
import path from 'node:path';
import {runE2E, run, sleep, waitFor, waitForOutput, watchIntervals} from './harness.mjs';

// Where the compare layer's cut is, in page pixels, and where the divider is.
const cutAndDivider = page => page.evaluate(() => {
  const {map, swipe} = window.seamap;
  const container = swipe.compare.getContainer();
  const left = Number(/rect\([^,]+,[^,]+,[^,]+,\s*(-?[\d.]+)px\)/.exec(container.style.clip)?.[1]);
  const box = map.getContainer().getBoundingClientRect();
  return {cut: container.getBoundingClientRect().left + left, divider: box.left + box.width * swipe.position,
    mapLeft: box.left, width: box.width, top: box.top, height: box.height};
});

await runE2E({name: 'swipe', timeoutMs: 120000}, async ({checks, work, seamap, sourceDir, launchBrowser, start, shot}) => {
  const survey = path.join(work, 'survey');
  const map = path.join(work, 'map.mbtiles');
  const config = path.join(work, 'both.json');
  fs.writeFileSync(config, JSON.stringify({layers: 'both', enhance: {ops: [{op: 'clahe'}]}}));
  await run(seamap, ['simulate', '--out', survey, '--frames', '16', '--line-length', '2', '--seed', '3', '--quiet']);
  await run(seamap, ['build', '--images', path.join(survey, 'photo'), '--nav', path.join(survey, 'nav.csv'),
    '--camera', path.join(survey, 'camera.json'), '--origin', '43.1,131.9', '--quiet', '--config', config, '--out', map]);
  const server = start(seamap, ['serve', map, '--host', '127.0.0.1', '--port', '0', '--web', path.join(sourceDir, 'web')]);
  await waitForOutput(server, /serving http:\/\/127\.0\.0\.1:\d+\//, 20000);
  const base = /serving (http:\/\/127\.0\.0\.1:\d+\/)/.exec(server.output)[1];

  const browser = await launchBrowser();
  const page = await browser.newPage({viewport: {width: 1100, height: 700}});
  page.setDefaultTimeout(10000);
  const errors = [];
  page.on('pageerror', e => errors.push(e.message));
  await watchIntervals(page);
  await page.goto(base);
  await page.waitForSelector('body[data-ready="true"]');

  await checks.run('a map with two layers offers the swipe', async () => {
    if (!await page.isVisible('#swipe')) throw new Error('no visible swipe switch');
    return await page.evaluate(() => [...window.seamap.layers.distinct.keys()].join(' and '));
  });

  await checks.run('switched on: the other layer over the one shown, named either side of the divider', async () => {
    await page.check('#swipe');
    await page.waitForSelector('.swipe-divider');
    const state = await page.evaluate(() => {
      const {map, layers, swipe} = window.seamap;
      return {onMap: map.hasLayer(swipe.compare) && map.hasLayer(layers.active), other: swipe.compare !== layers.active,
        left: document.querySelector('.swipe-labels .left').textContent,
        right: document.querySelector('.swipe-labels .right').textContent};
    });
    if (!state.onMap || !state.other) throw new Error(JSON.stringify(state));
    if (state.left !== 'raw' || state.right !== 'enhanced') throw new Error(`labels "${state.left}" | "${state.right}"`);
    const loaded = await waitFor('enhanced tiles right of the divider', () => page.evaluate(() => {
      const {map, swipe} = window.seamap;
      const box = map.getContainer().getBoundingClientRect();
      const middle = box.left + box.width / 2;
      return [...swipe.compare.getContainer().querySelectorAll('img.leaflet-tile')]
        .filter(img => img.complete && img.naturalWidth > 0 && img.getBoundingClientRect().right > middle).length || null;
    }), {timeoutMs: 10000});
    const at = await cutAndDivider(page);
    if (Math.abs(at.cut - at.divider) > 1) throw new Error(`cut at ${at.cut} px, divider at ${at.divider} px`);
    return `${state.left} | ${state.right}, ${loaded} enhanced tiles loaded`;
  });

  await checks.run('dragging the divider moves the cut, not the map', async () => {
    const at = await cutAndDivider(page);
    const centre = await page.evaluate(() => window.seamap.map.getCenter());
    const y = at.top + at.height * 0.6;
    await page.mouse.move(at.divider, y);
    await page.mouse.down();
    for (let i = 1; i <= 8; ++i) await page.mouse.move(at.divider - (at.width / 4) * (i / 8), y);
    await page.mouse.up();
    const after = await cutAndDivider(page);
    const moved = await page.evaluate(c => window.seamap.map.getCenter().distanceTo(c), centre);
    if (Math.abs(after.divider - (at.divider - at.width / 4)) > at.width * 0.02) {
      throw new Error(`divider at ${after.divider.toFixed(0)} px, dragged to ${(at.divider - at.width / 4).toFixed(0)}`);
    }
    if (Math.abs(after.cut - after.divider) > 1) throw new Error(`cut at ${after.cut} px, divider at ${after.divider} px`);
    if (moved > 0.001) throw new Error(`the map moved ${moved.toFixed(3)} m`);
    await shot(page, 'console-swipe');
    return `divider at ${((after.divider - after.mapLeft) / after.width * 100).toFixed(0)} % of the map`;
  });

  await checks.run('the cut stays at the divider when the map pans and zooms, and keys move it', async () => {
    await page.evaluate(() => window.seamap.map.panBy([120, -60], {animate: false}));
    await page.evaluate(() => window.seamap.map.zoomOut(1, {animate: false}));
    await sleep(200);
    const panned = await cutAndDivider(page);
    if (Math.abs(panned.cut - panned.divider) > 1) throw new Error(`after a pan: cut ${panned.cut}, divider ${panned.divider}`);
    await page.focus('.swipe-divider');
    for (let i = 0; i < 50; ++i) await page.keyboard.press('ArrowRight');
    const keyed = await cutAndDivider(page);
    if (!(keyed.divider > panned.divider + 10) || Math.abs(keyed.cut - keyed.divider) > 1) {
      throw new Error(`keys: divider ${panned.divider} -> ${keyed.divider}, cut ${keyed.cut}`);
    }
    return `off by ${Math.abs(panned.cut - panned.divider).toFixed(2)} px after a pan and zoom`;
  });

  await checks.run('the live stream asks for both layers while comparing, one after', async () => {
    const asked = () => page.evaluate(() => window.seamap.live.scope().layer);
    const both = await asked();
    if (both.split(',').sort().join(',') !== ',enhanced') throw new Error(`layers "${both}"`);
    await page.uncheck('#swipe');
    const state = await page.evaluate(() => {
      const {map, layers} = window.seamap;
      const enhanced = layers.distinct.get('enhanced');
      return {onMap: map.hasLayer(enhanced), clip: enhanced.getContainer()?.style.clip || '',
        divider: Boolean(document.querySelector('.swipe-divider'))};
    });
    if (state.onMap || state.clip || state.divider) throw new Error(`after switching off: ${JSON.stringify(state)}`);
    const one = await asked();
    if (one !== '') throw new Error(`layers "${one}" after switching off`);
    return `"${both}" then "${one}"`;
  });

  await checks.run('switched on and off twice: only the tile layers on the map keep a timer', async () => {
    for (let i = 0; i < 2; ++i) {
      await page.check('#swipe');
      await page.waitForSelector('.swipe-divider');
      await page.uncheck('#swipe');
    }
    const state = await page.evaluate(() => {
      const {map, layers} = window.seamap;
      let onMap = 0;
      map.eachLayer(layer => { if (layer instanceof layers.main.constructor) onMap++; });
      return {onMap, intervals: window.__e2eIntervalsFrom('/js/tile_layer.js')};
    });
    if (state.intervals !== state.onMap) throw new Error(`${state.onMap} tile layers on the map, ${state.intervals} intervals running`);
    return `${state.onMap} on the map, ${state.intervals} running`;
  });

  await checks.run('no script errors on the page', async () => {
    if (errors.length) throw new Error(errors.join('; '));
    return 'none';
  });
});
