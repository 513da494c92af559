// Map buttons an operator reaches for with one thumb: fit the mission, jump
// to the vehicle, follow it, fullscreen, help; the same as keyboard
// shortcuts (listed in the help box, `?`).

import {$} from './dom.js';

const L = window.L;

export const SHORTCUTS = [
  ['f', 'fit the whole mission'],
  ['v', 'jump to the vehicle'],
  ['l', 'follow the vehicle on/off'],
  ['p', 'map click: photos'],
  ['m', 'map click: measure'],
  ['a', 'map click: add a mark (with the token)'],
  ['c', 'copy the coordinates under the pointer'],
  ['b', 'low-bandwidth mode on/off'],
  ['u', 'fullscreen on/off'],
  ['?', 'this help'],
  ['Esc', 'close popups and the photo viewer'],
];

function button(container, {id, text, title, onClick}) {
  const b = L.DomUtil.create('a', 'view-button', container);
  b.id = id;
  b.href = '#';
  b.role = 'button';
  b.title = title;
  b.setAttribute('aria-label', title);
  b.textContent = text;
  L.DomEvent.on(b, 'click', event => {
    L.DomEvent.preventDefault(event);
    L.DomEvent.stopPropagation(event);
    onClick();
  });
  return b;
}

// actions: {fit(), vehicle(), toggleFollow(), fullscreen(), help()}
export function viewControls(map, actions) {
  const Control = L.Control.extend({
    options: {position: 'topleft'},
    onAdd() {
      const box = L.DomUtil.create('div', 'leaflet-bar view-controls');
      button(box, {id: 'view-fit', text: '⤢', title: 'fit the mission (f)', onClick: actions.fit});
      button(box, {id: 'view-vehicle', text: '◎', title: 'jump to the vehicle (v)', onClick: actions.vehicle});
      button(box, {id: 'view-follow', text: '⇢', title: 'follow the vehicle (l)', onClick: actions.toggleFollow});
      button(box, {id: 'view-fullscreen', text: '□', title: 'fullscreen (u)', onClick: actions.fullscreen});
      button(box, {id: 'view-help', text: '?', title: 'keyboard shortcuts (?)', onClick: actions.help});
      L.DomEvent.disableClickPropagation(box);
      return box;
    },
  });
  new Control().addTo(map);
}

export function showFollowing(on) {
  $('#view-follow')?.classList.toggle('active', on);
  const box = $('#follow');
  if (box) box.checked = on;
}

// Keyboard shortcuts (not while typing in a field).
export function keyboardShortcuts(handlers) {
  document.addEventListener('keydown', event => {
    if (event.ctrlKey || event.metaKey || event.altKey) return;
    const target = event.target;
    if (target && (target.isContentEditable || ['INPUT', 'SELECT', 'TEXTAREA'].includes(target.tagName))) return;
    const handler = handlers[event.key];
    if (!handler) return;
    event.preventDefault();
    handler();
  });
}

export function toggleHelp(force) {
  const box = $('#help');
  box.hidden = force === undefined ? !box.hidden : !force;
}

export function fillHelp() {
  const list = $('#help-keys');
  list.replaceChildren(...SHORTCUTS.flatMap(([key, what]) => {
    const dt = document.createElement('dt');
    const kbd = document.createElement('kbd');
    kbd.textContent = key;
    dt.append(kbd);
    const dd = document.createElement('dd');
    dd.textContent = what;
    return [dt, dd];
  }));
}
