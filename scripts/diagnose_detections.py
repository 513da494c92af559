#!/usr/bin/env python3
"""Why a recogniser misses objects and where its false detections lie, on a simulated survey (issue 32's weakest
stress conditions). Standard library only.

    scripts/diagnose_detections.py DETECTIONS.geojson LOW.geojson SURVEY/truth/objects.json [--radius 0.10]

DETECTIONS: `seamap detect` at the model's thresholds; LOW: the same map at `--min-score 0.1` (what the network
saw below the threshold). Matching as scripts/eval_detections.py (same class within the radius, nearest first,
one to one). Each missed object is put in the first that fits:
  position  a detection of its class 10-30 cm away (the box is there, its centre is off)
  class     a detection of another class within the radius (confused)
  score     in LOW, a detection of its class within the radius (scored under the threshold; its score given)
  none      nothing of its class within 30 cm even in LOW
Each false detection: duplicate (its object matched by another detection within 30 cm), offset (an unmatched
object of its class 10-30 cm away), confusion (an object of another class within 30 cm), clutter (a look-alike
of the truth's `negatives` within 0.5 m, its kind given), else texture. Prints one line per item, then counts.
"""
import argparse
import json
import math
from collections import Counter


def match(dets, truths, radius):
    pairs = sorted((math.dist(d["xy"], t["xy"]), i, k) for i, d in enumerate(dets) for k, t in enumerate(truths)
                   if d["class"] == t["class"] and math.dist(d["xy"], t["xy"]) <= radius)
    used_d, used_t, out = set(), set(), {}
    for dist, i, k in pairs:
        if i not in used_d and k not in used_t:
            used_d.add(i), used_t.add(k)
            out[k] = i
    return out


def load_dets(path):
    out = []
    for f in json.load(open(path))["features"]:
        p = f["properties"]
        out.append(dict(cls=p["class"], xy=tuple(p["position_m"][:2]), score=p.get("score", float("nan")),
                        level=p.get("level"), size=p.get("size_m"), truncated=p.get("truncated", False)))
        out[-1]["class"] = out[-1]["cls"]
    return out


def main():
    ap = argparse.ArgumentParser()
    ap.add_argument("detections")
    ap.add_argument("low")
    ap.add_argument("truth", help="SURVEY/truth/objects.json")
    ap.add_argument("--radius", type=float, default=0.10)
    a = ap.parse_args()
    truth = json.load(open(a.truth))
    objs = [dict(cls=o["class"], **{"class": o["class"]}, xy=(o["x_m"], o["y_m"]), size=o["size_m"],
                 buried=o.get("buried_fraction", 0)) for o in truth["objects"]]
    negs = [dict(cls=o["class"], xy=(o["x_m"], o["y_m"]), size=o["size_m"]) for o in truth.get("negatives", [])]
    dets, low = load_dets(a.detections), load_dets(a.low)
    matched = match(dets, objs, a.radius)
    counts = Counter()
    for k, o in enumerate(objs):
        if k in matched:
            continue
        near = lambda ds, same: sorted((math.dist(d["xy"], o["xy"]), d) for d in ds
                                       if (d["class"] == o["class"]) == same)
        same = [x for x in near(dets, True) if x[0] <= 0.30]
        other = [x for x in near(dets, False) if x[0] <= a.radius]
        lows = [x for x in near(low, True) if x[0] <= a.radius]
        lows30 = [x for x in near(low, True) if x[0] <= 0.30]
        if same:
            kind, why = "position", f"{same[0][1]['class']} {100 * same[0][0]:.1f} cm away, score {same[0][1]['score']:.2f}"
        elif other:
            kind, why = "class", f"taken for {other[0][1]['class']} (score {other[0][1]['score']:.2f})"
        elif lows:
            kind, why = "score", f"scored {lows[0][1]['score']:.2f} at {100 * lows[0][0]:.1f} cm (level {lows[0][1]['level']})"
        else:
            kind = "none"
            why = (f"best low-score {lows30[0][1]['class']} {100 * lows30[0][0]:.1f} cm away, score "
                   f"{lows30[0][1]['score']:.2f}" if lows30 else "nothing of its class within 30 cm at any score")
        counts["miss " + kind] += 1
        print(f"miss {kind:<8} {o['cls']:<7} size {o['size']:.2f} m buried {o['buried']:.2f} at "
              f"({o['xy'][0]:.2f}, {o['xy'][1]:.2f}): {why}")
    used = set(matched.values())
    for i, d in enumerate(dets):
        if i in used:
            continue
        def nearest(items, pred=lambda o: True):
            c = sorted((math.dist(d["xy"], o["xy"]), k, o) for k, o in enumerate(items) if pred(o))
            return c[0] if c else (math.inf, -1, None)
        dist_same, k_same, o_same = nearest(objs, lambda o: o["class"] == d["class"])
        dist_other, _, o_other = nearest(objs, lambda o: o["class"] != d["class"])
        dist_neg, _, o_neg = nearest(negs)
        if dist_same <= 0.30 and k_same in matched:
            kind, why = "duplicate", f"of a matched {d['class']} {100 * dist_same:.1f} cm away"
        elif dist_same <= 0.30:
            kind, why = "offset", f"an unmatched {d['class']} {100 * dist_same:.1f} cm away"
        elif dist_other <= 0.30:
            kind, why = "confusion", f"on a {o_other['cls']} ({100 * dist_other:.1f} cm)"
        elif dist_neg <= 0.5:
            kind, why = "clutter", f"on a look-alike '{o_neg['cls']}' ({100 * dist_neg:.0f} cm)"
        else:
            kind, why = "texture", f"nearest object {100 * min(dist_same, dist_other):.0f} cm, look-alike " + (
                f"{100 * dist_neg:.0f} cm" if negs else "none in this survey")
        counts["false " + kind] += 1
        print(f"false {kind:<9} {d['class']:<7} score {d['score']:.2f} level {d['level']} size {d['size']}: {why}")
    print("counts: " + (", ".join(f"{k} {v}" for k, v in sorted(counts.items())) or "nothing missed or false"))


if __name__ == "__main__":
    main()
