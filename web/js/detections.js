// Detections and operator marks: markers with popups (class, score, position,
// time, the photos that saw it), a side list filtered by class and score that
// zooms to the object, confirming or rejecting a recogniser's detection, and
// adding, editing, moving and deleting operator marks. In mark mode a drag
// draws a box around a missed object (the mark gets class and box: training
// data, issue 32); any class may be typed, the mission's classes are offered.

import {getCollection, missionUrl, send} from './api.js';
import {classColour} from './class_colour.js';
import {$, el, escapeHtml, toast} from './dom.js';
import {formatLatLon, formatMetres, formatTime} from './geo.js';

const L = window.L;

const escapeClass = name => String(name).toLowerCase().replace(/[^a-z0-9_-]/g, '_');


// A detector's score as a percentage; operator marks have none.
const scoreText = p => (p.source === 'operator' || p.score === null || p.score === undefined
  ? null : `${(Number(p.score) * 100).toFixed(0)}%`);

export class Detections {
  constructor(map, {canEdit, frame, openPhotos}) {
    this.map = map;
    this.canEdit = canEdit;     // () => bool: token set or not required
    this.frame = frame;         // local frame for east/north, or null
    this.openPhotos = openPhotos; // (frame ids, index) => the photo viewer on ids[index]
    this.features = new Map();  // id -> Feature
    this.markers = new Map();   // id -> L.Marker
    this.group = L.featureGroup().addTo(map);
    this.boxes = new Map();     // id -> L.Rectangle of an operator mark's box
    this.boxGroup = L.featureGroup().addTo(map);
    this.missionClasses = [];   // the mission's class table (/api/status classes)
    this.drawn = false;         // a box was just drawn: the click that ends it adds no point mark
    this.filter = '';
    this.lastSeq = 0;
    this.deleted = new Set();   // ids deleted on the server
    this.minScore = 0;          // recogniser detections below it are hidden (marks never)
    this.showRejected = true;
    $('#detection-class').addEventListener('change', event => {
      this.filter = event.target.value;
      this.render();
    });
    $('#detection-score').addEventListener('input', event => {
      this.minScore = Number(event.target.value) / 100;
      $('#detection-score-value').textContent = `≥ ${event.target.value}%`;
      this.render();
    });
    $('#detection-rejected').addEventListener('change', event => {
      this.showRejected = event.target.checked;
      this.render();
    });
  }

  async load() {
    const collection = await getCollection('/api/detections');
    this.lastSeq = collection.last_seq || 0;
    const seen = new Set();
    for (const feature of collection.features || []) {
      seen.add(String(feature.id));
      this.upsert(feature, false);
    }
    for (const id of [...this.features.keys()]) if (!seen.has(id)) this.remove(id, false);
    this.render();
  }

  // Events come batched: an update sent before a delete can arrive after the
  // console removed the mark, and must not bring it back.
  onEvent({action, id, feature}) {
    const key = String(id ?? feature?.id);
    if (action === 'deleted') {
      this.deleted.add(key);
      this.remove(key);
    } else if (feature && (action === 'created' || !this.deleted.has(key))) {
      this.deleted.delete(key);   // SQLite may give a deleted id to a new mark
      this.upsert(feature);
    }
  }

  upsert(feature, render = true) {
    const id = String(feature.id ?? feature.properties.id);
    const p = feature.properties;
    if (p.seq) this.lastSeq = Math.max(this.lastSeq, p.seq);
    this.features.set(id, feature);
    const [lon, lat] = feature.geometry.coordinates;
    let marker = this.markers.get(id);
    const editable = p.source === 'operator' && this.canEdit();
    // A stereo location has an orientation: an arrow along the object's x axis.
    const heading = Number.isFinite(p.heading_deg) ? Math.round(p.heading_deg * 10) / 10 : null;
    const iconKey = `${p.class}|${p.source}|${p.status}|${heading}`;
    const icon = L.divIcon({
      className: `detection-icon ${p.source === 'operator' ? 'operator' : 'detected'} class-${escapeClass(p.class)} status-${escapeClass(p.status || 'unconfirmed')}`,
      html: `<span data-detection-id="${escapeHtml(id)}" title="${escapeHtml(p.class)}" style="background:${classColour(p.class)}"></span>` +
        (heading === null ? '' : `<b class="heading" data-heading="${heading}" style="transform:rotate(${heading}deg)">↑</b>`),
      iconSize: [18, 18],
      iconAnchor: [9, 9],
      popupAnchor: [0, -8],
    });
    if (!marker) {
      marker = L.marker([lat, lon], {icon, draggable: editable, keyboard: true, title: p.class, riseOnHover: true});
      marker.bindPopup(() => this.popup(id), {minWidth: 200, maxWidth: 280});
      marker.on('dragstart', () => { marker.beingDragged = true; });
      marker.on('dragend', () => {
        marker.beingDragged = false;
        this.move(id, marker.getLatLng());
      });
      this.markers.set(id, marker);
    } else {
      // A live update must not yank a marker from under the operator's
      // pointer, nor swap its element (that would end a drag): the position
      // waits for the drop, the icon changes only with the class.
      if (!marker.beingDragged) marker.setLatLng([lat, lon]);
      if (marker.iconKey !== iconKey) marker.setIcon(icon);
      if (marker.dragging) editable ? marker.dragging.enable() : marker.dragging.disable();
      if (marker.isPopupOpen()) this.refreshPopup(id, marker);
    }
    marker.iconKey = iconKey;
    marker.getElement()?.setAttribute('data-detection-id', id);
    this.boxes.get(id)?.remove();
    this.boxes.delete(id);
    if (p.source === 'operator' && Array.isArray(p.box) && p.box.length === 5) {
      const rect = L.rectangle(p.box.map(([x, y]) => [y, x]),
        {color: classColour(p.class), weight: 2, fill: false, interactive: false, className: 'mark-box'});
      rect.detectionId = id;
      this.boxes.set(id, rect);
    }
    if (render) this.render();
  }

  // A live update of an open popup keeps the operator's typing: while its
  // form is being edited only the facts above the form are replaced.
  refreshPopup(id, marker) {
    const box = marker.getPopup().getElement()?.querySelector('.detection-popup');
    const form = box?.querySelector('.mark-form');
    const editing = form && (form.contains(document.activeElement) ||
      [...form.querySelectorAll('input')].some(input => input.value !== input.defaultValue));
    const fresh = this.popup(id);
    if (!editing || typeof fresh === 'string') {
      marker.setPopupContent(fresh);
      return;
    }
    fresh.querySelector('.mark-form')?.remove();
    for (const child of [...box.children]) if (child !== form) child.remove();
    form.before(...fresh.childNodes);   // (popup.update() would rebuild the form too)
  }

  remove(id, render = true) {
    const marker = this.markers.get(id);
    if (marker) {
      const popup = marker.getPopup()?.getElement();
      this.group.removeLayer(marker);
      popup?.remove();   // at once: a popup fading out for 200 ms still takes clicks
    }
    this.markers.delete(id);
    this.features.delete(id);
    this.boxes.get(id)?.remove();
    this.boxes.delete(id);
    if (render) this.render();
  }

  // Whether the filters (class, score, rejected) let a detection through.
  shown(p) {
    if (this.filter && p.class !== this.filter) return false;
    if (p.source === 'operator') return true;
    if (p.status === 'rejected' && !this.showRejected) return false;
    return Number(p.score ?? 1) >= this.minScore - 1e-9;
  }

  // Markers on the map and the side list follow the filters.
  render() {
    const classes = [...new Set([...this.features.values()].map(f => f.properties.class))].sort();
    const select = $('#detection-class');
    const current = this.filter;
    select.replaceChildren(el('option', {value: ''}, `all classes (${this.features.size})`),
      ...classes.map(c => el('option', {value: c, selected: c === current}, c)));
    if (current && !classes.includes(current)) this.filter = '';
    const offered = [...new Set([...this.missionClasses, ...classes])].sort();
    $('#class-names').replaceChildren(...offered.map(c => el('option', {value: c})));

    const list = $('#detection-list');
    const items = [];
    const sorted = [...this.features.entries()].sort((a, b) => (a[1].properties.time_s ?? 1e18) - (b[1].properties.time_s ?? 1e18));
    for (const [id, feature] of sorted) {
      const marker = this.markers.get(id);
      const shown = this.shown(feature.properties);
      if (shown && !this.group.hasLayer(marker)) this.group.addLayer(marker);
      if (!shown && this.group.hasLayer(marker)) this.group.removeLayer(marker);
      const rect = this.boxes.get(id);
      if (rect && shown && !this.boxGroup.hasLayer(rect)) this.boxGroup.addLayer(rect);
      if (rect && !shown && this.boxGroup.hasLayer(rect)) this.boxGroup.removeLayer(rect);
      if (marker.getElement()) marker.getElement().setAttribute('data-detection-id', id);
      if (!shown) continue;
      const p = feature.properties;
      items.push(el('li', {dataset: {id, class: p.class, source: p.source, status: p.status || ''}, tabindex: '0',
        onclick: () => this.focus(id),
        onkeydown: event => { if (event.key === 'Enter') this.focus(id); }},
        el('span', {class: `swatch ${p.source === 'operator' ? 'operator' : 'detected'}`, style: `background:${classColour(p.class)}`}),
        el('strong', {}, p.class),
        el('span', {class: 'list-score'}, ` ${scoreText(p) ?? 'mark'}`),
        p.source !== 'operator' && p.status && p.status !== 'unconfirmed' ? el('small', {class: 'list-status'}, ` ${p.status}`) : null,
        p.time_s !== null && p.time_s !== undefined ? el('small', {}, ` t ${formatTime(p.time_s)}`) : null));
    }
    list.replaceChildren(...items);
    list.dataset.count = String(items.length);
    $('#detection-count').textContent = String(this.features.size);
    this.renderLegend(classes);
  }

  // The class colours on the map, with counts; a click filters by the class.
  renderLegend(classes) {
    if (!this.legend) {
      const Legend = L.Control.extend({
        options: {position: 'bottomright'},
        onAdd: () => {
          const box = L.DomUtil.create('div', 'class-legend');
          L.DomEvent.disableClickPropagation(box);
          return box;
        },
      });
      this.legend = new Legend().addTo(this.map);
    }
    const box = this.legend.getContainer();
    box.hidden = classes.length === 0;
    const count = c => [...this.features.values()].filter(f => f.properties.class === c).length;
    box.replaceChildren(...classes.map(c => el('div', {class: 'entry', dataset: {class: c},
      title: 'show only this class', onclick: () => {
        this.filter = this.filter === c ? '' : c;
        this.render();
      }},
    el('span', {class: 'swatch', style: `background:${classColour(c)}`}), `${c} (${count(c)})`)),
    el('div', {class: 'shapes'}, '● recognised ◆ operator mark'));
    box.dataset.filter = this.filter;
  }

  focus(id) {
    const marker = this.markers.get(id);
    if (!marker) return;
    this.map.setView(marker.getLatLng(), Math.max(this.map.getZoom(), this.map.getMaxZoom() - 3));
    marker.openPopup();
    document.body.classList.remove('panel-open');
  }

  popup(id) {
    const feature = this.features.get(id);
    if (!feature) return 'deleted';
    const p = feature.properties;
    const [lon, lat] = feature.geometry.coordinates;
    let where = formatLatLon(lat, lon);
    if (this.frame) {
      const {east, north} = this.frame.toLocal(lat, lon);
      where += ` (E ${formatMetres(east)}, N ${formatMetres(north)})`;
    }
    const box = el('div', {class: 'detection-popup', dataset: {id}},
      el('h3', {class: 'popup-class'}, p.class),
      el('dl', {},
        scoreText(p) ? [el('dt', {}, 'score'), el('dd', {class: 'popup-score'}, Number(p.score).toFixed(2))] : null,
        el('dt', {}, 'source'), el('dd', {}, p.source === 'operator' ? 'operator mark' : (p.source || '–')),
        p.model ? [el('dt', {}, 'model'), el('dd', {}, p.model)] : null,
        p.source !== 'operator' ? [el('dt', {}, 'status'), el('dd', {class: 'popup-status'}, p.status || 'unconfirmed')] : null,
        p.size_m ? [el('dt', {}, 'size'), el('dd', {}, `${formatMetres(p.size_m[0])} × ${formatMetres(p.size_m[1])}`)] : null,
        Number.isFinite(p.heading_deg) ? [el('dt', {}, 'heading'), el('dd', {class: 'popup-heading'}, `${Number(p.heading_deg).toFixed(1)}°`)] : null,
        Number.isFinite(p.depth_m) ? [el('dt', {}, 'depth'), el('dd', {}, formatMetres(p.depth_m))] : null,
        Number.isFinite(p.sigma_m) ? [el('dt', {}, 'uncertainty'), el('dd', {class: 'popup-sigma'}, `± ${(1000 * p.sigma_m).toFixed(1)} mm`)] : null,
        el('dt', {}, 'position'), el('dd', {}, where),
        el('dt', {}, 'time'), el('dd', {}, formatTime(p.time_s)),
        p.note ? [el('dt', {}, 'note'), el('dd', {}, p.note)] : null),
      this.photoStrip(p));
    if (p.source === 'operator' && this.canEdit()) box.append(this.editForm(id, p));
    if (p.source !== 'operator' && this.canEdit()) box.append(this.reviewButtons(id, p));
    return box;
  }

  // The photos that saw it (best first), each opening the photo viewer.
  photoStrip(p) {
    const ids = (p.frames && p.frames.length ? p.frames
      : (p.frame_id !== null && p.frame_id !== undefined ? [p.frame_id] : [])).slice(0, 6);
    if (!ids.length) return null;
    const open = index => event => {
      if (!this.openPhotos) return;   // no viewer: the link opens the photo
      event.preventDefault();
      this.openPhotos(ids, index);
    };
    return el('div', {class: `photo-strip${ids.length === 1 ? ' single' : ''}`},
      ...ids.map((frameId, index) => el('a', {href: missionUrl(`/api/frames/${frameId}/image`), target: '_blank', rel: 'noopener',
        dataset: {frame: frameId}, title: `photo ${frameId}`, onclick: open(index)},
      el('img', {class: 'thumb', src: missionUrl(`/api/frames/${frameId}/image?max=256`), alt: `frame ${frameId}`, loading: 'lazy'}))));
  }

  // A recogniser's detection: the operator confirms or rejects it (PATCH status).
  reviewButtons(id, p) {
    const set = status => async () => {
      try {
        const feature = await send('PATCH', `/api/detections/${id}`, {status});
        this.upsert(feature);
        toast(`detection ${id} ${status}`);
      } catch (error) {
        toast(`${status === 'unconfirmed' ? 'undo' : status.replace(/ed$/, '')} failed: ${error.message}`);
      }
    };
    return el('div', {class: 'buttons review'},
      p.status !== 'confirmed' ? el('button', {type: 'button', class: 'confirm', onclick: set('confirmed')}, 'confirm') : null,
      p.status !== 'rejected' ? el('button', {type: 'button', class: 'danger reject', onclick: set('rejected')}, 'reject') : null,
      p.status === 'confirmed' || p.status === 'rejected'
        ? el('button', {type: 'button', class: 'undo', onclick: set('unconfirmed')}, 'undo') : null);
  }

  editForm(id, p) {
    const cls = el('input', {name: 'class', value: p.class, list: 'class-names', required: true, 'aria-label': 'class'});
    const note = el('input', {name: 'note', value: p.note || '', placeholder: 'note', 'aria-label': 'note'});
    return el('form', {class: 'mark-form', onsubmit: async event => {
      event.preventDefault();
      try {
        // A Feature with only properties: the geometry stays where it is.
        const feature = await send('PATCH', `/api/detections/${id}`,
          {type: 'Feature', properties: {class: cls.value.trim(), note: note.value}});
        this.upsert(feature);
        toast('mark saved');
      } catch (error) {
        toast(`save failed: ${error.message}`);
      }
    }},
    cls, note,
    el('div', {class: 'buttons'},
      el('button', {type: 'submit'}, 'save'),
      el('button', {type: 'button', class: 'danger', onclick: () => this.delete(id)}, 'delete')),
    el('small', {}, 'drag the marker to move it'));
  }

  async move(id, latlng) {
    try {
      const feature = await send('PATCH', `/api/detections/${id}`,
        {type: 'Feature', geometry: {type: 'Point', coordinates: [latlng.lng, latlng.lat]}});
      this.upsert(feature);
    } catch (error) {
      toast(`move failed: ${error.message}`);
      const old = this.features.get(id);
      if (old) this.upsert(old);
    }
  }

  async delete(id) {
    if (!confirm('Delete this mark?')) return;
    try {
      await send('DELETE', `/api/detections/${id}`);
      this.deleted.add(id);
      this.remove(id);
    } catch (error) {
      toast(`delete failed: ${error.message}`);
    }
  }

  // The mission's class table: offered to the operator with the classes on the map.
  setMissionClasses(classes) {
    this.missionClasses = Array.isArray(classes) ? classes.filter(c => typeof c === 'string') : [];
    this.render();
  }

  // Mark mode: a drag on the map draws a box; on release the new-mark form
  // opens at its centre with the box. A press without a drag is a click
  // (a point mark). The map does not pan while a box is drawn.
  enableBoxDrawing(isMarkMode) {
    const map = this.map;
    let start = null, rect = null;
    map.on('mousedown', event => {
      if (!isMarkMode() || !this.canEdit() || event.originalEvent.button !== 0) return;
      start = event;
      map.dragging.disable();
    });
    map.on('mousemove', event => {
      if (!start) return;
      const moved = start.containerPoint.distanceTo(event.containerPoint);
      if (!rect && moved < 6) return;
      const bounds = L.latLngBounds(start.latlng, event.latlng);
      if (!rect) rect = L.rectangle(bounds, {weight: 2, dashArray: '4 3', fill: false, className: 'drawing-box'}).addTo(map);
      else rect.setBounds(bounds);
    });
    const finish = () => {
      if (!start) return;
      map.dragging.enable();
      start = null;
      if (!rect) return;
      const bounds = rect.getBounds();
      rect.remove();
      rect = null;
      this.drawn = true;   // the click that follows the release is no point mark
      setTimeout(() => { this.drawn = false; }, 0);
      this.addAt(bounds.getCenter(), bounds);
    };
    map.on('mouseup', finish);
    document.addEventListener('mouseup', finish);
  }

  // Whether a box was just drawn (then the map's click adds nothing).
  justDrew() {
    return this.drawn;
  }

  // Map click in "mark" mode: a popup form that creates an operator mark;
  // with `bounds` (a drawn box) the mark carries that box.
  addAt(latlng, bounds = null) {
    const cls = el('input', {name: 'class', list: 'class-names', required: true, placeholder: 'class', 'aria-label': 'class'});
    const note = el('input', {name: 'note', placeholder: 'note', 'aria-label': 'note'});
    const popup = L.popup({minWidth: 200}).setLatLng(latlng);
    const box = bounds ? [[bounds.getWest(), bounds.getNorth()], [bounds.getWest(), bounds.getSouth()],
      [bounds.getEast(), bounds.getSouth()], [bounds.getEast(), bounds.getNorth()],
      [bounds.getWest(), bounds.getNorth()]] : null;
    if (box) popup.on('remove', () => this.pending?.remove());
    this.pending?.remove();
    this.pending = box ? L.rectangle(bounds, {weight: 2, fill: false, className: 'pending-box'}).addTo(this.map) : null;
    const form = el('form', {class: 'mark-form new-mark', onsubmit: async event => {
      event.preventDefault();
      try {
        const feature = await send('POST', '/api/detections', {
          type: 'Feature',
          geometry: {type: 'Point', coordinates: [latlng.lng, latlng.lat]},
          properties: {class: cls.value.trim(), note: note.value, ...(box ? {box} : {})},
        });
        this.map.closePopup(popup);
        this.upsert(feature);
        toast(`mark ${feature.id} added`);
      } catch (error) {
        toast(`add failed: ${error.message}`);
      }
    }}, el('h3', {}, box ? 'new mark with a box' : 'new mark'), cls, note,
    el('small', {}, 'any class: a new one joins the mission\'s list'),
    el('div', {class: 'buttons'}, el('button', {type: 'submit'}, 'add')));
    popup.setContent(form).openOn(this.map);
    setTimeout(() => cls.focus(), 0);
  }

  toGeoJSON() {
    return {type: 'FeatureCollection', features: [...this.features.values()]};
  }
}
