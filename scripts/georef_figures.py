#!/usr/bin/env python3
"""The figures of docs/GEOREF.md, as SVG, from simulated surveys (standard library only).

  scripts/georef_figures.py SEAMAP_BINARY OUT_DIR [SEEDS]

georef_plan.svg: plan view of one survey (GPS sigma 1.5 m, seed 1): the true
path, the buoy's fixes, the keyframes georeferenced by `--method tether`
(the default; filled where the model's tether is taut, hollow where slack)
and the paper's triangle.
georef_residuals.svg: histograms of the along- and cross-track errors of the
tether keyframes of that survey.
georef_rmse.svg: RMSE over all keyframes against GPS sigma for tether,
umeyama (the default before issue 31) and the triangle, mean over SEEDS
surveys (default 10), with the GPS-only bound of the spec's section 4
(report.json's gps_bound_rmse_m) and tether's predicted_rmse_m.
"""
import csv
import json
import math
import os
import statistics
import subprocess
import sys


def run(*args):
    subprocess.run([str(a) for a in args], check=True, stdout=subprocess.DEVNULL, stderr=subprocess.DEVNULL)


def read_csv(path):
    with open(path, newline='') as f:
        return list(csv.DictReader(f))


class Local:
    """East/north metres about a survey's first truth row (plotting only: the
    truth file gives both lat/lon and x/y, so the scale is read off it)."""

    def __init__(self, truth):
        a = truth[0]
        self.lat0, self.lon0 = float(a['lat']), float(a['lon'])
        self.x0, self.y0 = float(a['x_m']), float(a['y_m'])
        self.m_per_deg_lat = 111132.954 - 559.822 * math.cos(2 * math.radians(self.lat0))
        self.m_per_deg_lon = 111412.84 * math.cos(math.radians(self.lat0))

    def __call__(self, lat, lon):
        return (self.x0 + (float(lon) - self.lon0) * self.m_per_deg_lon,
                self.y0 + (float(lat) - self.lat0) * self.m_per_deg_lat)


class Svg:
    def __init__(self, width, height):
        self.width, self.height, self.items = width, height, []

    def add(self, text):
        self.items.append(text)

    def save(self, path):
        with open(path, 'w') as f:
            f.write(f'<svg xmlns="http://www.w3.org/2000/svg" width="{self.width}" height="{self.height}" '
                    f'viewBox="0 0 {self.width} {self.height}" font-family="sans-serif" font-size="12">\n'
                    f'<rect width="100%" height="100%" fill="white"/>\n' + '\n'.join(self.items) + '\n</svg>\n')


class Axes:
    """A plot area mapping data to pixels, with ticks and labels."""

    def __init__(self, svg, box, xr, yr, xlabel, ylabel, logy=False, equal=False):
        self.svg, self.logy = svg, logy
        self.x0, self.y0, self.w, self.h = box
        if logy:
            yr = (math.log10(yr[0]), math.log10(yr[1]))
        if equal:  # same metres per pixel on both axes
            sx, sy = (xr[1] - xr[0]) / self.w, (yr[1] - yr[0]) / self.h
            s = max(sx, sy)
            cx, cy = sum(xr) / 2, sum(yr) / 2
            xr, yr = (cx - s * self.w / 2, cx + s * self.w / 2), (cy - s * self.h / 2, cy + s * self.h / 2)
        self.xr, self.yr = xr, yr
        svg.add(f'<rect x="{self.x0}" y="{self.y0}" width="{self.w}" height="{self.h}" fill="none" stroke="#444"/>')
        svg.add(f'<text x="{self.x0 + self.w / 2}" y="{self.y0 + self.h + 36}" text-anchor="middle">{xlabel}</text>')
        svg.add(f'<text transform="translate({self.x0 - 48},{self.y0 + self.h / 2}) rotate(-90)" '
                f'text-anchor="middle">{ylabel}</text>')
        for v in nice_ticks(*xr):
            px = self.px(v, None)[0]
            svg.add(f'<line x1="{px:.1f}" y1="{self.y0 + self.h}" x2="{px:.1f}" y2="{self.y0 + self.h + 4}" stroke="#444"/>'
                    f'<text x="{px:.1f}" y="{self.y0 + self.h + 17}" text-anchor="middle">{v:g}</text>')
        for v in (log_ticks(*yr) if logy else nice_ticks(*yr)):
            py = self.y0 + self.h - (v - self.yr[0]) / (self.yr[1] - self.yr[0]) * self.h
            label = f'{10 ** v:g}' if logy else f'{v:g}'
            svg.add(f'<line x1="{self.x0 - 4}" y1="{py:.1f}" x2="{self.x0}" y2="{py:.1f}" stroke="#444"/>'
                    f'<text x="{self.x0 - 7}" y="{py + 4:.1f}" text-anchor="end">{label}</text>')

    def px(self, x, y):
        px = self.x0 + (x - self.xr[0]) / (self.xr[1] - self.xr[0]) * self.w
        if y is None:
            return px, None
        if self.logy:
            y = math.log10(y)
        return px, self.y0 + self.h - (y - self.yr[0]) / (self.yr[1] - self.yr[0]) * self.h

    def line(self, points, colour, width=1.5, dash=None):
        d = ' '.join(f'{a:.1f},{b:.1f}' for a, b in (self.px(x, y) for x, y in points))
        self.svg.add(f'<polyline points="{d}" fill="none" stroke="{colour}" stroke-width="{width}"'
                     f'{f" stroke-dasharray={chr(34)}{dash}{chr(34)}" if dash else ""}/>')

    def dots(self, points, colour, r=2, fill=True):
        self.svg.add(f'<g stroke="{colour}" fill="{colour if fill else "none"}" stroke-width="0.8">')
        for x, y in points:
            a, b = self.px(x, y)
            self.svg.add(f'<circle cx="{a:.1f}" cy="{b:.1f}" r="{r}"/>')
        self.svg.add('</g>')


def nice_ticks(lo, hi, n=6):
    step = 10 ** math.floor(math.log10((hi - lo) / n))
    for m in (1, 2, 5, 10):
        if (hi - lo) / (step * m) <= n:
            step *= m
            break
    v = math.ceil(lo / step) * step
    out = []
    while v <= hi + 1e-9:
        out.append(round(v, 10))
        v += step
    return out


def log_ticks(lo, hi):
    return [float(e) for e in range(math.ceil(lo), math.floor(hi) + 1)]


def legend(svg, x, y, entries):
    for i, (label, colour, kind) in enumerate(entries):
        yy = y + 16 * i
        if kind == 'line':
            svg.add(f'<line x1="{x}" y1="{yy}" x2="{x + 20}" y2="{yy}" stroke="{colour}" stroke-width="2"/>')
        elif kind == 'dash':
            svg.add(f'<line x1="{x}" y1="{yy}" x2="{x + 20}" y2="{yy}" stroke="{colour}" stroke-width="2" '
                    f'stroke-dasharray="4 3"/>')
        else:
            svg.add(f'<circle cx="{x + 10}" cy="{yy}" r="3" stroke="{colour}" '
                    f'fill="{colour if kind == "dot" else "none"}"/>')
        svg.add(f'<text x="{x + 26}" y="{yy + 4}">{label}</text>')


def georef(seamap, survey, method, out, name):
    nav, report = os.path.join(out, f'{name}.csv'), os.path.join(out, f'{name}.json')
    run(seamap, 'georef', '--keyframes', os.path.join(survey, 'keyframes.txt'), '--buoy',
        os.path.join(survey, 'buoy.csv'), '--tether-length', 30, '--depth-csv', os.path.join(survey, 'depth.csv'),
        '--method', method, '--out', nav, '--report', report, '--quiet')
    evaluation = os.path.join(out, f'{name}_eval.json')
    run(seamap, 'georef-eval', '--nav', nav, '--truth', survey, '--json', evaluation)
    return read_csv(nav), json.load(open(report)), json.load(open(evaluation))


def plan_and_residuals(seamap, out):
    survey = os.path.join(out, 'survey_plan')
    run(seamap, 'simulate-buoy', '--out', survey, '--force', '--gps-sigma', 1.5, '--seed', 1, '--cloud-points', 0)
    truth = read_csv(os.path.join(survey, 'truth.csv'))
    fixes = read_csv(os.path.join(survey, 'buoy.csv'))
    nav, _, ev = georef(seamap, survey, 'tether', out, 'plan_tether')
    tri_nav, tri_report, tri_ev = georef(seamap, survey, 'triangle', out, 'plan_triangle')
    local = Local(truth)
    path = [(float(r['x_m']), float(r['y_m'])) for r in truth]
    buoy = [local(r['lat'], r['lon']) for r in fixes]
    keyframes = [(local(r['lat'], r['lon']), r['good'] != '0') for r in nav]
    by_time = {round(float(r['time_s']), 3): local(r['lat'], r['lon']) for r in tri_nav}
    vertices = [by_time.get(round(k['time_s'], 3)) for k in tri_report['triangle']['keyframes']]

    xs = [p[0] for p in path + buoy]
    ys = [p[1] for p in path + buoy]
    svg = Svg(900, 760)
    ax = Axes(svg, (70, 40, 800, 640), (min(xs) - 5, max(xs) + 5), (min(ys) - 5, max(ys) + 5), 'east (m)',
              'north (m)', equal=True)
    ax.dots(buoy, '#c77dff', r=1.2)
    ax.line(path, '#222', width=1.2)
    ax.dots([p for p, good in keyframes if not good], '#999', r=1.8, fill=False)
    ax.dots([p for p, good in keyframes if good], '#2a9d3a', r=1.4)
    if all(vertices):
        ax.line(vertices + vertices[:1], '#e63946', width=1.5, dash='5 3')
    svg.add(f'<text x="70" y="24" font-size="14">Plan view, GPS sigma 1.5 m, seed 1: tether RMSE '
            f'{ev["rmse_m"] * 100:.1f} cm over {ev["keyframes"]} keyframes, the triangle '
            f'{tri_ev["rmse_m"] * 100:.0f} cm</text>')
    legend(svg, 640, 60, [('true path', '#222', 'line'), ('buoy GPS fixes', '#c77dff', 'dot'),
                          ('keyframes, taut tether', '#2a9d3a', 'dot'), ('keyframes, slack', '#999', 'ring'),
                          ("paper's triangle", '#e63946', 'dash')])
    svg.save(os.path.join(out, 'georef_plan.svg'))

    # Along- and cross-track errors: along the true heading, and to its right.
    along, cross = [], []
    for t, (p, _) in zip(truth, keyframes):
        dx, dy = p[0] - float(t['x_m']), p[1] - float(t['y_m'])
        h = math.radians(float(t['heading_deg']))
        along.append(100 * (dx * math.sin(h) + dy * math.cos(h)))
        cross.append(100 * (dx * math.cos(h) - dy * math.sin(h)))
    svg = Svg(900, 380)
    for i, (name, values) in enumerate((('along-track', along), ('cross-track', cross))):
        lo, hi, width = -30, 30, 2
        bins = [0] * ((hi - lo) // width)
        for v in values:  # the last bins take what lies beyond
            bins[min(len(bins) - 1, max(0, int((v - lo) // width)))] += 1
        ax = Axes(svg, (70 + 430 * i, 40, 360, 280), (lo, hi), (0, max(bins) * 1.1), f'{name} error (cm)',
                  'keyframes')
        for k, n in enumerate(bins):
            a, b = ax.px(lo + width * k, n)
            c, d = ax.px(lo + width * (k + 1), 0)
            svg.add(f'<rect x="{a:.1f}" y="{b:.1f}" width="{c - a - 1:.1f}" height="{d - b:.1f}" fill="#457b9d"/>')
        svg.add(f'<text x="{80 + 430 * i}" y="30">{name}: mean {statistics.mean(values):+.1f} cm, '
                f'sd {statistics.pstdev(values):.1f} cm</text>')
    svg.save(os.path.join(out, 'georef_residuals.svg'))


def rmse_against_sigma(seamap, out, seeds):
    survey = os.path.join(out, 'survey_sigma')
    sigmas, rows = (0.5, 1.5, 2.5), {}
    for sigma in sigmas:
        for seed in range(1, seeds + 1):
            run(seamap, 'simulate-buoy', '--out', survey, '--force', '--gps-sigma', sigma, '--seed', seed,
                '--cloud-points', 0)
            _, report, ev = georef(seamap, survey, 'tether', out, 'w')
            _, _, ume = georef(seamap, survey, 'umeyama', out, 'u')
            _, _, tri = georef(seamap, survey, 'triangle', out, 't')
            rows.setdefault(sigma, []).append((ev['rmse_m'], tri['rmse_m'], report['gps_bound_rmse_m'],
                                               ume['rmse_m'], report['predicted_rmse_m']))
            print(f'sigma {sigma} seed {seed}: tether {ev["rmse_m"]:.3f} m, umeyama {ume["rmse_m"]:.3f} m,'
                  f' triangle {tri["rmse_m"]:.3f} m', file=sys.stderr)
    # RMS over the seeds (the error estimate predicts an RMS)
    mean = {s: [math.sqrt(statistics.mean(r[k] ** 2 for r in rows[s])) for k in range(5)] for s in sigmas}
    svg = Svg(640, 460)
    ax = Axes(svg, (80, 40, 520, 360), (0, 3), (0.01, 30), 'GPS sigma (m)', 'RMSE over all keyframes (m)', logy=True)
    for k, colour, dash in ((1, '#e63946', None), (3, '#f4a261', None), (0, '#2a9d3a', None), (2, '#555', '4 3'),
                            (4, '#2a9d3a', '2 3')):
        points = [(s, mean[s][k]) for s in sigmas]
        ax.line(points, colour, width=2, dash=dash)
        ax.dots(points, colour, r=3)
    svg.add(f'<text x="80" y="24" font-size="14">RMSE against GPS sigma, RMS of {seeds} surveys each</text>')
    legend(svg, 95, 185, [("paper's triangle", '#e63946', 'line'), ('umeyama (before issue 31)', '#f4a261', 'line'),
                           ('seamap (tether)', '#2a9d3a', 'line'), ('tether predicted', '#2a9d3a', 'dash'),
                           ('bound (GPS only)', '#555', 'dash')])
    svg.save(os.path.join(out, 'georef_rmse.svg'))
    for s in sigmas:
        w, t, b, u, p = mean[s]
        print(f'sigma {s}: tether {w:.3f} m (predicted {p:.3f}), umeyama {u:.3f} m, triangle {t:.3f} m,'
              f' bound {b:.3f} m, tether/bound {w / b:.2f}, triangle/tether {t / w:.0f}x')


def main():
    if len(sys.argv) < 3:
        sys.exit(__doc__)
    seamap, out = sys.argv[1], sys.argv[2]
    seeds = int(sys.argv[3]) if len(sys.argv) > 3 else 10
    os.makedirs(out, exist_ok=True)
    plan_and_residuals(seamap, out)
    rmse_against_sigma(seamap, out, seeds)


if __name__ == '__main__':
    main()
