#!/usr/bin/env python3
"""Scores a recogniser's detections against a simulated survey's truth (standard library only).

    scripts/eval_detections.py DETECTIONS.geojson SURVEY/truth/objects.csv [MORE.geojson MORE/objects.csv ...]
                               [--radius 0.10]

Matching (docs/DETECT.md): all same-class pairs (detection, truth) within the
radius, nearest first, assigned greedily one to one. Positions are the
mission's east/north metres (GeoJSON property position_m, truth x_m, y_m: the
same origin when the map was built with the survey's). Prints one line per
class and overall: truths, detections, matches, recall, precision, median and
p90 position error; then class-agnostic recall and the class confusions.
Several surveys: each matched on its own, the counts pooled.
"""
import argparse
import csv
import json
import math
import sys


def percentile(values, p):
    if not values:
        return float("nan")
    v = sorted(values)
    return v[min(len(v) - 1, round(p * (len(v) - 1)))]


def match(dets, truths, radius, same_class=True):
    pairs = []
    for i, d in enumerate(dets):
        for k, t in enumerate(truths):
            if same_class and d["class"] != t["class"]:
                continue
            dist = math.hypot(d["x"] - t["x"], d["y"] - t["y"])
            if dist <= radius:
                pairs.append((dist, i, k))
    pairs.sort()
    used_d, used_t, out = set(), set(), []
    for dist, i, k in pairs:
        if i not in used_d and k not in used_t:
            used_d.add(i), used_t.add(k), out.append((dist, i, k))
    return out


def load(detections_path, truth_path):
    with open(detections_path) as f:
        features = json.load(f)["features"]
    dets = [{"class": f["properties"]["class"], "x": f["properties"]["position_m"][0],
             "y": f["properties"]["position_m"][1]} for f in features]
    with open(truth_path, newline="") as f:
        truths = [{"class": r["class"], "x": float(r["x_m"]), "y": float(r["y_m"])} for r in csv.DictReader(f)]
    if not truths:
        sys.exit(f"{truth_path}: no objects")
    return dets, truths


def main():
    ap = argparse.ArgumentParser(description="pairs of DETECTIONS.geojson TRUTH.csv, one pair per survey (pooled)")
    ap.add_argument("pairs", nargs="+", metavar="DETECTIONS TRUTH")
    ap.add_argument("--radius", type=float, default=0.10)
    a = ap.parse_args()
    if len(a.pairs) % 2:
        sys.exit("expected pairs: DETECTIONS.geojson TRUTH.csv [DETECTIONS.geojson TRUTH.csv ...]")
    dets, truths, matches, agnostic = [], [], [], []
    for k in range(0, len(a.pairs), 2):  # each survey on its own (its own origin), then pooled
        d, t = load(a.pairs[k], a.pairs[k + 1])
        matches += [(dist, i + len(dets), j + len(truths)) for dist, i, j in match(d, t, a.radius)]
        agnostic += [(dist, i + len(dets), j + len(truths)) for dist, i, j in match(d, t, a.radius, False)]
        dets += d
        truths += t
    classes = sorted({t["class"] for t in truths} | {d["class"] for d in dets})
    print("class      truths  dets  matched  recall  precision  median_cm  p90_cm")
    for cls in classes + ["all"]:
        nt = sum(1 for t in truths if cls in ("all", t["class"]))
        nd = sum(1 for d in dets if cls in ("all", d["class"]))
        m = [dist for dist, i, k in matches if cls in ("all", truths[k]["class"])]
        rec = len(m) / nt if nt else float("nan")
        prec = len(m) / nd if nd else float("nan")
        print(f"{cls:<10} {nt:6d} {nd:5d} {len(m):8d} {rec:7.2f} {prec:10.2f} {100 * percentile(m, 0.5):10.1f} "
              f"{100 * percentile(m, 0.9):7.1f}")
    print(f"class-agnostic recall {len(agnostic) / len(truths):.2f}")
    confused = {}
    for dist, i, k in agnostic:
        if dets[i]["class"] != truths[k]["class"]:
            key = (truths[k]["class"], dets[i]["class"])
            confused[key] = confused.get(key, 0) + 1
    for (t, d), n in sorted(confused.items()):
        print(f"confusion: {n} {t} detected as {d}")


if __name__ == "__main__":
    main()
