// Checks of the console's own controls against a running replay (called by
// console.e2e.mjs with the token already set): marks added, edited, moved and
// deleted through the popups; no score for marks; the class legend; the
// cursor readout; measuring; fit, follow and the view in the URL; help.

import {sleep, waitFor} from './harness.mjs';

const api = async (base, path) => {
  const response = await fetch(new URL(path, base));
  return {status: response.status, body: response.status === 200 ? await response.json() : null};
};

// Screen position of a lat/lon on the page.
const screenOf = (page, lat, lon) => page.evaluate(([la, lo]) => {
  const {map} = window.seamap;
  const p = map.latLngToContainerPoint([la, lo]);
  const box = map.getContainer().getBoundingClientRect();
  return {x: box.left + p.x, y: box.top + p.y};
}, [lat, lon]);

export async function checkConsoleTools({browser, page, checks, base, shot}) {
  await page.uncheck('#follow');
  let id = null;

  await checks.run('a mark is added with the console\'s own controls', async () => {
    await page.check('#mode-mark');
    const box = await page.$eval('#map', el => {
      const r = el.getBoundingClientRect();
      return {x: r.left + r.width * 0.3, y: r.top + r.height * 0.7};
    });
    // (A click while the map still settles can be taken for a drag: try twice.)
    for (let attempt = 0; attempt < 2; ++attempt) {
      await sleep(500);
      await page.mouse.click(box.x, box.y);
      if (await page.waitForSelector('.leaflet-popup .new-mark', {timeout: 5000}).catch(() => null)) break;
    }
    await page.waitForSelector('.leaflet-popup .new-mark', {timeout: 1000});
    await page.fill('.leaflet-popup .new-mark input[name="class"]', 'e2e-rock');
    await page.fill('.leaflet-popup .new-mark input[name="note"]', 'added by clicking');
    await page.click('.leaflet-popup .new-mark button[type="submit"]');
    const li = await page.waitForSelector('#detection-list li[data-class="e2e-rock"]', {state: 'attached', timeout: 5000});
    id = await li.getAttribute('data-id');
    const stored = await api(base, `api/detections/${id}`);
    if (stored.status !== 200 || stored.body.properties.note !== 'added by clicking') {
      throw new Error(`the server has ${JSON.stringify(stored.body)}`);
    }
    const listed = (await li.textContent()).trim();
    if (/%/.test(listed)) throw new Error(`the list shows a score for a mark: "${listed}"`);
    await page.check('#mode-photos');
    return `mark ${id}: "${listed}"`;
  });
  if (!id) return;

  const openPopup = async () => {
    await page.evaluate(markId => window.seamap.detections.markers.get(markId).openPopup(), id);
    await page.waitForSelector(`.leaflet-popup .detection-popup[data-id="${id}"]`, {timeout: 5000});
  };

  await checks.run('a mark\'s class and note are edited in its popup (no made-up score)', async () => {
    await openPopup();
    if (await page.$('.leaflet-popup .popup-score')) throw new Error('the popup shows a score for an operator mark');
    const form = '.leaflet-popup .mark-form:not(.new-mark)';
    await page.fill(`${form} input[name="class"]`, 'e2e-boulder');
    await page.fill(`${form} input[name="note"]`, 'edited in the popup');
    await page.click(`${form} button[type="submit"]`);
    await waitFor('the edit stored', async () => {
      const {body} = await api(base, `api/detections/${id}`);
      return body && body.properties.class === 'e2e-boulder' && body.properties.note === 'edited in the popup';
    }, {timeoutMs: 5000});
    await page.waitForSelector('#detection-list li[data-class="e2e-boulder"]', {state: 'attached', timeout: 5000});
    const toast = await page.textContent('#toast');
    if (/failed/.test(toast)) throw new Error(`toast says "${toast}"`);
    await shot(page, 'console-mark-edit');
    await page.evaluate(() => window.seamap.map.closePopup());
    return 'class and note saved';
  });

  await checks.run('the class legend shows the class in its colour', async () => {
    const entry = await page.waitForSelector('.class-legend .entry[data-class="e2e-boulder"]', {timeout: 5000});
    const [legendColour, markerColour] = await page.evaluate(markId => [
      getComputedStyle(document.querySelector('.class-legend .entry[data-class="e2e-boulder"] .swatch')).backgroundColor,
      getComputedStyle(document.querySelector(`.leaflet-marker-icon [data-detection-id="${markId}"]`)).backgroundColor,
    ], id);
    if (legendColour !== markerColour) throw new Error(`legend ${legendColour}, marker ${markerColour}`);
    const other = await page.evaluate(() => getComputedStyle(document.querySelector('.class-legend .entry[data-class="e2e-anchor"] .swatch')).backgroundColor);
    if (other === legendColour) throw new Error('two classes share one colour');
    return `${(await entry.textContent()).trim()}: ${legendColour}`;
  });

  await checks.run('a mark is moved by dragging it', async () => {
    const before = (await api(base, `api/detections/${id}`)).body.geometry.coordinates;
    const drag = async () => {
      const marker = await page.$(`.leaflet-marker-icon[data-detection-id="${id}"]`);
      const box = await marker.boundingBox();
      const from = {x: box.x + box.width / 2, y: box.y + box.height / 2};
      await page.mouse.move(from.x, from.y);
      await page.mouse.down();
      for (let i = 1; i <= 10; ++i) await page.mouse.move(from.x + 6 * i, from.y + 4 * i);
      // Leaflet moves the marker in an animation frame after each mouse move; on
      // a loaded machine the drop can come before the last one: wait for two.
      await page.evaluate(() => new Promise(resolve => requestAnimationFrame(() => requestAnimationFrame(resolve))));
      await page.mouse.up();
      return from;
    };
    const stored = async () => {
      const {body} = await api(base, `api/detections/${id}`);
      const c = body.geometry.coordinates;
      return c[0] !== before[0] && c[1] !== before[1] ? c : null;
    };
    let from = await drag();
    let after = await waitFor('the move stored', stored, {timeoutMs: 3000}).catch(() => null);
    let tries = 1;
    if (!after) {
      // Under a loaded suite the first press can land while the previous edit's
      // live event is redrawn (CI saw it once in many runs): an operator drags again.
      from = await drag();
      tries = 2;
      after = await waitFor('the move stored', stored, {timeoutMs: 5000});
    }
    const at = await screenOf(page, after[1], after[0]);
    const off = Math.hypot(at.x - (from.x + 60), at.y - (from.y + 40));
    if (off > 6) throw new Error(`stored ${off.toFixed(1)} px from where it was dropped`);
    if ((await api(base, `api/detections/${id}`)).body.properties.class !== 'e2e-boulder') throw new Error('the move lost the class');
    return `dropped within ${off.toFixed(1)} px${tries > 1 ? ' (second drag)' : ''}`;
  });

  await checks.run('a mark is deleted from its popup', async () => {
    await openPopup();
    page.once('dialog', dialog => dialog.accept());
    await page.click('.leaflet-popup .mark-form button.danger');
    await waitFor('the mark gone', async () => (await api(base, `api/detections/${id}`)).status === 404, {timeoutMs: 5000});
    await page.waitForSelector(`#detection-list li[data-id="${id}"]`, {state: 'detached', timeout: 5000});
    // Not even fading out: an invisible popup would still take the next map click.
    if (await page.$(`.leaflet-popup .detection-popup[data-id="${id}"]`)) throw new Error('its popup is still on the map');
    return '404 and off the list';
  });

  await checks.run('the cursor readout follows the pointer and clears when it leaves the map', async () => {
    const box = await page.$eval('#map', el => {
      const r = el.getBoundingClientRect();
      return {x: r.left + r.width / 2, y: r.top + r.height / 2, left: r.left};
    });
    await page.mouse.move(box.x, box.y);
    await page.mouse.move(box.x + 5, box.y + 5);
    const shown = await page.textContent('#cursor');
    if (!/°N|°S/.test(shown)) throw new Error(`readout "${shown}" over the map`);
    await page.mouse.move(Math.max(2, box.left - 100), box.y);   // over the panel
    const left = await waitFor('an empty readout', async () => (await page.textContent('#cursor')) === '' || null,
      {timeoutMs: 2000}).catch(async () => { throw new Error(`still "${await page.textContent('#cursor')}"`); });
    return `"${shown}" -> cleared${left ? '' : ''}`;
  });

  await checks.run('measuring: a path\'s length and the area it encloses', () => measuring().finally(async () => {
    await page.click('#measure-clear');   // pass or fail, the next checks start in photos mode
    await page.check('#mode-photos');
  }));

  async function measuring() {
    await page.check('#mode-measure');
    const box = await page.$eval('#map', el => {
      const r = el.getBoundingClientRect();
      return {x: r.left + r.width / 2, y: r.top + r.height / 2};
    });
    const pts = [[box.x - 100, box.y + 80], [box.x + 100, box.y + 80], [box.x - 100, box.y - 80]];
    const under = [];
    for (const [x, y] of pts) {
      under.push(await page.evaluate(([px, py]) => {
        const e = document.elementFromPoint(px, py);
        return e ? `${e.tagName.toLowerCase()}.${[...e.classList].join('.')}` : 'nothing';
      }, [x, y]));
      await page.mouse.click(x, y);
      await sleep(150);
    }
    const result = await page.$eval('#measure-result', el => ({metres: Number(el.dataset.metres), area: Number(el.dataset.area)}));
    const legs = await page.evaluate(([a, b, c]) => {
      const {map} = window.seamap;
      const box = map.getContainer().getBoundingClientRect();
      const ll = ([x, y]) => map.containerPointToLatLng([x - box.left, y - box.top]);
      return {ab: map.distance(ll(a), ll(b)), ac: map.distance(ll(a), ll(c)), bc: map.distance(ll(b), ll(c))};
    }, pts);
    const area = legs.ab * legs.ac / 2;
    if (Math.abs(result.metres - (legs.ab + legs.bc)) > 0.01 * result.metres) {
      throw new Error(`length ${result.metres} m, expected ${(legs.ab + legs.bc).toFixed(3)}; clicked on ${under.join(', ')}`);
    }
    if (!(Math.abs(result.area - area) < 0.01 * area)) throw new Error(`area ${result.area} m², expected ${area.toFixed(3)}`);
    await shot(page, 'console-measure');
    return `${result.metres.toFixed(2)} m, ${result.area.toFixed(2)} m²`;
  }

  await checks.run('fit shows the whole track; follow keeps the vehicle in view', async () => {
    await page.evaluate(() => window.seamap.map.setView([0, 0], 3, {animate: false}));
    await page.click('#view-fit');
    await sleep(300);
    const fitted = await page.evaluate(() => {
      const {map, track} = window.seamap;
      const b = map.getBounds();
      return track.points.every(p => b.contains(p));
    });
    if (!fitted) throw new Error('track points outside the fitted view');
    await page.evaluate(() => window.seamap.map.setView([0, 0], 18, {animate: false}));
    await page.click('#view-follow');
    if (!await page.isChecked('#follow')) throw new Error('follow is not on');
    const inView = await waitFor('the vehicle in view', () => page.evaluate(() => {
      const {map, vehicle} = window.seamap;
      return map.getBounds().contains(vehicle.marker.getLatLng());
    }), {timeoutMs: 5000});
    await page.click('#view-follow');
    return inView ? 'both' : '';
  });

  await checks.run('the view is in the URL: a reload opens the same place', async () => {
    const want = await page.evaluate(() => {
      const {map, track} = window.seamap;
      const p = track.points[Math.floor(track.points.length / 2)];
      map.setView(p, map.getMaxZoom() - 4, {animate: false});
      return {lat: p.lat, lng: p.lng, zoom: map.getZoom()};
    });
    await sleep(600);
    const url = page.url();
    if (!/#.*z=/.test(url)) throw new Error(`no view in ${url}`);
    const context = await browser.newContext({viewport: {width: 1280, height: 800}});
    const other = await context.newPage();
    try {
      await other.goto(url, {waitUntil: 'domcontentloaded'});
      await other.waitForSelector('body[data-ready="true"]', {timeout: 20000});
      const got = await other.evaluate(() => {
        const {map} = window.seamap;
        return {lat: map.getCenter().lat, lng: map.getCenter().lng, zoom: map.getZoom()};
      });
      const metres = await page.evaluate(([a, b]) => window.seamap.map.distance(a, b), [[want.lat, want.lng], [got.lat, got.lng]]);
      if (got.zoom !== want.zoom || metres > 0.05) throw new Error(`opened at z${got.zoom}, ${metres.toFixed(3)} m off (${url})`);
      await other.goto(url.replace(/#.*/, '#z=20&c=0,0&follow=1'), {waitUntil: 'domcontentloaded'});
      await other.reload({waitUntil: 'domcontentloaded'});
      await other.waitForSelector('body[data-ready="true"]', {timeout: 20000});
      if (!await other.isChecked('#follow')) throw new Error('follow=1 in the URL did not turn following on');
      return url.replace(/^[^#]*/, '');
    } finally {
      await context.close();
    }
  });

  await checks.run('the help box lists the keyboard shortcuts', async () => {
    await page.mouse.click(5, 5);
    await page.keyboard.press('?');
    await page.waitForSelector('#help:not([hidden])', {timeout: 2000});
    const keys = await page.$$eval('#help-keys dt', dts => dts.length);
    if (keys < 8) throw new Error(`${keys} shortcuts listed`);
    await page.keyboard.press('Escape');
    await page.waitForSelector('#help', {state: 'hidden', timeout: 2000});
    return `${keys} shortcuts`;
  });

  await checks.run('the footprints layer outlines the photos in view; a click opens one', async () => {
    await page.evaluate(() => window.seamap.fitMission());
    await sleep(300);
    await page.check('#footprints');
    const drawn = await waitFor('footprints drawn', async () => {
      const n = await page.$$eval('path.footprint', paths => paths.length);
      return n > 0 ? n : 0;
    }, {timeoutMs: 5000});
    const bbox = await page.evaluate(() => {
      const b = window.seamap.map.getBounds().pad(0.2);
      return [b.getWest(), b.getSouth(), b.getEast(), b.getNorth()].map(v => v.toFixed(7)).join(',');
    });
    const api = await (await fetch(new URL(`api/footprints?bbox=${bbox}`, base))).json();
    if (Math.abs(api.features.length - drawn) > 3) throw new Error(`${drawn} drawn, the API lists ${api.features.length}`);
    const id = await page.evaluate(() => {
      const {footprints, photos} = window.seamap;
      const some = footprints.layer.getLayers()[Math.floor(footprints.layer.getLayers().length / 2)];
      some.fire('click', {latlng: some.getBounds().getCenter()});
      return some.feature.properties.id;
    });
    await page.waitForSelector('#photo-full[data-state="loaded"]', {timeout: 10000});
    const src = await page.getAttribute('#photo-full', 'src');
    if (!src.includes(`/api/frames/${id}/image`)) throw new Error(`viewer shows ${src}, not frame ${id}`);
    await page.click('#photo-next');
    await waitFor('the next frame', async () => (await page.getAttribute('#photo-full', 'src')).includes(`/api/frames/${id + 1}/image`), {timeoutMs: 5000});
    await shot(page, 'console-footprints');
    await page.click('#photo-viewer-close');
    await page.uncheck('#footprints');
    return `${drawn} outlines, frame ${id} opened, then ${id + 1}`;
  });
}
