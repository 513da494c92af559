// Photos under a point: a map click asks /api/frames?lat&lon for the photos
// whose footprint covers it, lists them with thumbnails and outlines their
// footprints; a photo opens at full resolution in the viewer.

import {getJSON, missionUrl} from './api.js';
import {$, el, toast} from './dom.js';
import {formatTime} from './geo.js';

const L = window.L;

export class Photos {
  constructor(map) {
    this.map = map;
    this.footprints = L.featureGroup().addTo(map);
    this.pin = L.circleMarker([0, 0], {radius: 5, color: '#00e5ff', weight: 2, fillOpacity: 0.4, interactive: false});
    this.request = 0;
    $('#photo-viewer-close').addEventListener('click', () => this.closeViewer());
    $('#photo-viewer').addEventListener('click', event => {
      if (event.target.id === 'photo-viewer') this.closeViewer();
    });
    this.frames = [];
    this.index = -1;
    $('#photo-prev').addEventListener('click', () => this.step(-1));
    $('#photo-next').addEventListener('click', () => this.step(1));
    document.addEventListener('keydown', event => {
      if ($('#photo-viewer').hidden) return;
      if (event.key === 'Escape') this.closeViewer();
      if (event.key === 'ArrowLeft') this.step(-1);
      if (event.key === 'ArrowRight') this.step(1);
    });
  }

  async at(latlng) {
    const request = ++this.request;
    this.pin.setLatLng(latlng).addTo(this.map);
    const list = $('#photo-list');
    list.dataset.state = 'loading';
    let frames;
    try {
      ({frames} = await getJSON(`/api/frames?lat=${latlng.lat.toFixed(9)}&lon=${latlng.lng.toFixed(9)}`));
    } catch (error) {
      if (request === this.request) {
        list.dataset.state = 'error';
        toast(`photos: ${error.message}`);
      }
      return;
    }
    if (request !== this.request) return;   // a newer click won
    this.footprints.clearLayers();
    $('#photo-summary').textContent = frames.length
      ? `${frames.length} photo${frames.length > 1 ? 's' : ''} cover this point`
      : 'no photo covers this point';
    list.replaceChildren(...frames.map(frame => this.item(frame)));
    list.dataset.state = 'ready';
    list.dataset.count = String(frames.length);
    this.frames = frames;
    if (frames.length) {
      this.outline(frames[0], true);
      document.body.dataset.panel = 'photos';
      // On a phone the list is in the collapsed panel: open it at the photos.
      if (matchMedia('(max-width: 720px)').matches) {
        document.body.classList.add('panel-open');
        $('#photos').scrollIntoView({block: 'start'});
      }
    }
  }

  item(frame) {
    const thumb = missionUrl(frame.thumb_url || `/api/frames/${frame.id}/image?max=256`);
    return el('li', {dataset: {id: frame.id}, tabindex: '0',
      onclick: () => this.open(frame),
      onkeydown: event => { if (event.key === 'Enter') this.open(frame); },
      onmouseenter: () => this.outline(frame, true)},
    el('img', {class: 'thumb', src: thumb, alt: `photo ${frame.id}`, loading: 'lazy'}),
    el('div', {class: 'meta'},
      el('strong', {}, frame.image || `frame ${frame.id}`),
      el('small', {}, `t ${formatTime(frame.time_s)} · alt ${Number(frame.altitude_m ?? 0).toFixed(2)} m · hdg ${Number(frame.heading_deg ?? 0).toFixed(0)}°`)));
  }

  outline(frame, only) {
    if (!frame.footprint) return;
    if (only) this.footprints.clearLayers();
    L.polygon(frame.footprint.map(([lon, lat]) => [lat, lon]),
      {color: '#00e5ff', weight: 1.5, fill: false, interactive: false}).addTo(this.footprints);
  }

  // Opens one frame by id (a footprint clicked): its neighbours by id are previous/next.
  async openId(id) {
    try {
      const frame = await getJSON(`/api/frames/${id}`);
      this.frames = [frame];
      const neighbours = await Promise.allSettled([getJSON(`/api/frames/${id - 1}`), getJSON(`/api/frames/${id + 1}`)]);
      if (neighbours[0].status === 'fulfilled') this.frames.unshift(neighbours[0].value);
      if (neighbours[1].status === 'fulfilled') this.frames.push(neighbours[1].value);
      this.open(frame);
    } catch (error) {
      toast(`photo ${id}: ${error.message}`);
    }
  }

  // Opens the photos with these ids (those that saw a detection), the
  // viewer's previous/next stepping through them; starts at ids[start].
  async openList(ids, start = 0) {
    const got = await Promise.allSettled(ids.map(id => getJSON(`/api/frames/${id}`)));
    const frames = got.filter(r => r.status === 'fulfilled').map(r => r.value);
    if (!frames.length) {
      toast(`photo ${ids[start]}: not found`);
      return;
    }
    this.frames = frames;
    this.open(frames.find(f => f.id === ids[start]) || frames[0]);
  }

  // Previous / next photo of the list in the viewer.
  step(delta) {
    if (!this.frames.length) return;
    this.open(this.frames[(this.index + delta + this.frames.length) % this.frames.length]);
  }

  open(frame) {
    this.index = this.frames.indexOf(frame);
    $('#photo-prev').disabled = $('#photo-next').disabled = this.frames.length < 2;
    this.outline(frame, true);
    const viewer = $('#photo-viewer');
    const img = $('#photo-full');
    img.removeAttribute('src');
    img.dataset.state = 'loading';
    img.onload = () => { img.dataset.state = 'loaded'; };
    img.onerror = () => { img.dataset.state = 'error'; };
    img.src = missionUrl(frame.image_url || `/api/frames/${frame.id}/image`);
    img.alt = frame.image || `frame ${frame.id}`;
    $('#photo-caption').textContent = `${frame.image || 'frame ' + frame.id} · t ${formatTime(frame.time_s)} · ` +
      `depth ${Number(frame.depth_m ?? 0).toFixed(1)} m · altitude ${Number(frame.altitude_m ?? 0).toFixed(2)} m`;
    $('#photo-open').href = img.src;
    viewer.hidden = false;
  }

  closeViewer() {
    $('#photo-viewer').hidden = true;
  }
}
