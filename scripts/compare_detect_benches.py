#!/usr/bin/env python3
"""Two runs of the stress bench side by side, and whether the second model may replace the first (standard library).

    scripts/compare_detect_benches.py BEFORE_DIR AFTER_DIR [--max-loss 0.02]

Each DIR holds `scripts/bench_detect.sh`'s stress_CONDITION.eval files (the same conditions in both). Prints recall
and precision per condition and per class (counts pooled over the conditions), before -> after, and the rule of
docs/DETECTION_MODEL.md ("Robust fine-tune"): keep the new model only if the pooled recall and precision both
improve and no condition and no class loses more than --max-loss of either. Exit status 0: keep; 1: do not.
"""
import argparse
import glob
import os
import sys


def read_eval(path):
    """{class or 'all': (truths, detections, matched)} from one eval_detections.py output."""
    rows = {}
    for line in open(path):
        f = line.split()
        if len(f) >= 4 and f[0] != "class" and f[1].isdigit() and f[2].isdigit() and f[3].isdigit():
            rows[f[0]] = (int(f[1]), int(f[2]), int(f[3]))
    if "all" not in rows:
        raise SystemExit(f"{path}: no 'all' row (expected scripts/eval_detections.py output)")
    return rows


def rates(t, d, m):
    return m / t if t else float("nan"), m / d if d else float("nan")


def main():
    ap = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    ap.add_argument("before")
    ap.add_argument("after")
    ap.add_argument("--max-loss", type=float, default=0.02)
    a = ap.parse_args()
    runs = []
    for d in (a.before, a.after):
        evals = {os.path.basename(p)[len("stress_"):-len(".eval")]: read_eval(p)
                 for p in sorted(glob.glob(os.path.join(d, "stress_*.eval")))}
        if not evals:
            raise SystemExit(f"{d}: no stress_*.eval (expected a scripts/bench_detect.sh output folder)")
        runs.append(evals)
    conditions = [c for c in runs[0] if c in runs[1]]
    if len(conditions) != len(runs[0]) or len(conditions) != len(runs[1]):
        print(f"note: comparing the conditions both runs have: {' '.join(conditions)}")

    def pooled(evals, key):
        t = d = m = 0
        for c in conditions:
            t1, d1, m1 = evals[c].get(key, (0, 0, 0))
            t, d, m = t + t1, d + d1, m + m1
        return t, d, m

    classes = sorted({k for r in runs for c in conditions for k in r[c] if k != "all"})
    worse = []
    print("| condition / class | objects | recall before -> after | precision before -> after |")
    print("| --- | --- | --- | --- |")
    items = [(c, runs[0][c]["all"], runs[1][c]["all"]) for c in conditions]
    items += [(f"class {k}", pooled(runs[0], k), pooled(runs[1], k)) for k in classes]
    for name, b, n in items:
        rb, pb = rates(*b)
        rn, pn = rates(*n)
        print(f"| {name} | {b[0]} | {rb:.2f} -> {rn:.2f} | {pb:.2f} -> {pn:.2f} |")
        for what, x, y in (("recall", rb, rn), ("precision", pb, pn)):
            if x == x and y == y and y < x - a.max_loss - 1e-9:
                worse.append(f"{name} {what} {x:.2f} -> {y:.2f}")
    b, n = pooled(runs[0], "all"), pooled(runs[1], "all")
    rb, pb = rates(*b)
    rn, pn = rates(*n)
    print(f"| **pooled** | {b[0]} | **{rb:.2f} -> {rn:.2f}** | **{pb:.2f} -> {pn:.2f}** |")
    improves = rn > rb and pn > pb
    keep = improves and not worse
    print(f"pooled recall and precision both improve: {'yes' if improves else 'no'}; losses over {a.max_loss}: "
          f"{'; '.join(worse) if worse else 'none'}")
    print("verdict: " + ("keep the new model" if keep else "do not ship the new model"))
    return 0 if keep else 1


if __name__ == "__main__":
    sys.exit(main())
