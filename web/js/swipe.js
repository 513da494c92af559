// Swipe to compare two photo layers (raw and enhanced): the other layer is
// laid over the one shown and cut at a divider the operator drags with the
// mouse or a finger, or moves with the arrow keys. Left of the divider: the
// layer shown; right: the other one.

import {$, el} from './dom.js';
import {link} from './link.js';
import {twinLayer} from './map.js';

const L = window.L;

export class Swipe {
  // layers(): addPhotoLayers' result (distinct layers, the active one), or
  // null while the map has no tiles yet.
  constructor(map, layers, onChange = () => {}) {
    this.map = map;
    this.layers = layers;
    this.onChange = onChange;
    this.compare = null;   // the layer right of the divider while comparing
    this.divider = el('input', {type: 'range', class: 'swipe-divider', min: '0', max: '1', step: '0.001',
      value: '0.5', 'aria-label': 'swipe divider: left the layer shown, right the other'});
    this.labels = el('div', {class: 'swipe-labels'}, el('span', {class: 'left'}), el('span', {class: 'right'}));
    // The divider is dragged, not the map under it.
    L.DomEvent.disableClickPropagation(this.divider);
    L.DomEvent.on(this.divider, 'pointerdown mousedown touchstart', L.DomEvent.stopPropagation);
    this.divider.addEventListener('input', () => this.clip());
    map.on('move zoom resize', () => this.clip());
    link.onModeChange(() => { if (this.compare) this.setOn(true); });   // tiles in the other format
  }

  get photoLayers() {
    return this.layers();
  }

  get available() {
    return Boolean(this.photoLayers) && this.photoLayers.distinct.size > 1;
  }

  // The divider's position as a fraction of the map's width.
  get position() {
    return Number(this.divider.value);
  }

  setOn(on) {
    if (on && !this.available) return;
    if (this.compare) {
      this.map.removeLayer(this.compare);
      this.compare = null;
      this.divider.remove();
      this.labels.remove();
    }
    if (on) {
      const {distinct, active, nameOf} = this.photoLayers;
      const other = [...distinct.values()].find(layer => layer !== active);
      this.compare = twinLayer(other).setOpacity(active.options.opacity).addTo(this.map).bringToFront();
      this.labels.querySelector('.left').textContent = nameOf(active);
      this.labels.querySelector('.right').textContent = nameOf(other);
      this.map.getContainer().append(this.divider, this.labels);
      this.clip();
    }
    this.onChange();
  }

  // Clips the compare layer to the right of the divider, in the coordinates
  // of the map pane (which moves when the map is panned).
  clip() {
    const container = this.compare?.getContainer();
    if (!container) return;
    const size = this.map.getSize();
    const nw = this.map.containerPointToLayerPoint([0, 0]);
    const se = this.map.containerPointToLayerPoint(size);
    const x = nw.x + size.x * this.position;
    container.style.clip = `rect(${nw.y}px, ${se.x}px, ${se.y}px, ${x}px)`;
    this.labels.style.setProperty('--divider-px', `${size.x * this.position}px`);
  }

  // The panel's checkbox: shown only for a mission with two photo layers.
  bindCheckbox(box = $('#swipe')) {
    this.box = box;
    this.showCheckbox();
    box.addEventListener('change', () => this.setOn(box.checked));
    // The layer switch changes which layer is shown: compare the other one.
    this.map.on('baselayerchange', () => {
      if (this.compare) this.setOn(true);
    });
  }

  showCheckbox() {
    this.box.closest('label').hidden = !this.available;
  }
}
