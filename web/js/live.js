// What moves while the mission is built or replayed: the vehicle marker
// (rotated by heading, at the estimated pose) and the progress bar with the
// mission status. The track lines are track.js and tracks.js.

import {$} from './dom.js';
import {formatTime} from './geo.js';

const L = window.L;

export class Vehicle {
  constructor(map) {
    this.map = map;
    this.follow = false;
    this.marker = L.marker([0, 0], {
      icon: L.divIcon({
        className: 'vehicle-icon',
        html: '<svg viewBox="-12 -12 24 24" width="28" height="28"><path d="M0,-11 L7,9 L0,5 L-7,9 Z"/></svg>',
        iconSize: [28, 28],
        iconAnchor: [14, 14],
      }),
      interactive: false,
      keyboard: false,
      zIndexOffset: 1000,
    });
  }

  update(pose) {
    if (!pose) return;
    const latlng = [pose.lat, pose.lon];
    this.marker.setLatLng(latlng);
    if (!this.map.hasLayer(this.marker)) this.marker.addTo(this.map);
    const arrow = this.marker.getElement()?.querySelector('svg');
    if (arrow) arrow.style.transform = `rotate(${pose.heading_deg || 0}deg)`;
    const info = $('#pose');
    if (info) {
      info.textContent = `frame ${pose.frame} · heading ${(pose.heading_deg ?? 0).toFixed(0)}° · ` +
        `depth ${(pose.depth_m ?? 0).toFixed(1)} m · alt ${(pose.altitude_m ?? 0).toFixed(2)} m · t ${formatTime(pose.time_s)}`;
    }
    if (this.follow) this.map.panTo(latlng, {animate: false});
  }
}

// How the mission's poses were estimated (seamap_trajectory metadata), in a line.
function describeTrajectory(t) {
  if (!t || !t.mode) return '';
  if (t.mode === 'refine' && t.live && t.registered_cross_line === undefined) {
    return 'trajectory: refined as the frames come (replay --refine-nav); the whole dive again at its end';
  }
  if (t.mode === 'refine') {
    const mm = (v) => Number(v ?? 0).toFixed(1);
    return `trajectory refined: ${t.registered_cross_line ?? 0} cross-line and ${t.registered_along_track ?? 0} ` +
      `along-track links (median ${t.median_inliers ?? 0} inliers), residual ${mm(t.residual_before_mm)} → ` +
      `${mm(t.residual_after_mm)} mm, ${t.nav_only_frames ?? 0} frames on navigation only`;
  }
  return `trajectory: ${t.mode} filter online`;
}

// 75 -> "1 min 15 s", 4000 -> "1 h 07 min".
export function formatDuration(seconds) {
  const s = Math.max(0, Math.round(seconds));
  if (s < 60) return `${s} s`;
  if (s < 3600) return `${Math.floor(s / 60)} min ${String(s % 60).padStart(2, '0')} s`;
  return `${Math.floor(s / 3600)} h ${String(Math.floor(s / 60) % 60).padStart(2, '0')} min`;
}

export function showStatus(status) {
  if (!status) return;
  const bar = $('#progress');
  const fraction = Math.max(0, Math.min(1, Number(status.progress) || 0));
  bar.value = fraction;
  bar.dataset.value = fraction.toFixed(4);
  bar.dataset.state = status.state || '';
  const label = $('#progress-label');
  const pct = (fraction * 100).toFixed(0);
  const fps = Number(status.frames_per_s) || 0;
  const rate = fps ? ` · ${fps.toFixed(1)} frames/s` : '';
  const left = Number(status.frames_total) - Number(status.frames_done);
  const eta = status.state === 'building' && fps > 0 && left > 0 ? ` · ${formatDuration(left / fps)} left` : '';
  label.textContent = `${status.state || ''}${status.replay ? ' (replay)' : ''} · ${status.frames_done ?? 0}/${status.frames_total ?? '?'} frames · ${pct}%${rate}${eta}`;
  label.dataset.eta = eta ? String(Math.round(left / fps)) : '';
  $('#mission-name').textContent = status.name || 'SeaMap';
  const tiles = $('#tiles-written');
  if (tiles) tiles.textContent = `${status.tiles_written ?? 0} tiles written, ${status.frames_rejected ?? 0} frames rejected`;
  const trajectory = $('#trajectory-status');
  if (trajectory) trajectory.textContent = describeTrajectory(status.trajectory);
  document.body.dataset.state = status.state || '';
}
