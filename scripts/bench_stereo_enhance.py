#!/usr/bin/env python3
"""Seed 004's enhancement chain in front of the stereo features (docs/STEREO.md
"Enhancement in front of the stereo features"): simulate-stereo scenes in
degraded water -> stereo-model and stereo-locate (one pair), each with
--feature-enhance off, auto and default; per water: the left/right inliers per
pair (stereo points), the model inliers of the located pair and the check-point
error against truth, raw vs enhanced.
usage: bench_stereo_enhance.py SEAMAP OUT_DIR SCENES"""
import json, math, os, statistics, subprocess, sys

seamap, out, scenes = sys.argv[1], sys.argv[2], int(sys.argv[3])
waters = {"degraded": "--haze 0.2 --noise 3 --blur 0.6", "murky": "--haze 0.35 --noise 5 --blur 0.8",
          "dark murky": "--haze 0.5 --noise 6 --blur 1.0"}
modes = ("off", "auto", "default")


def run(args):
    p = subprocess.run([seamap] + args, capture_output=True, text=True)
    return p.returncode, p.stdout + p.stderr


def inv(m):
    r = [[m[j][i] for j in range(3)] for i in range(3)]
    t = [-sum(r[i][k] * m[k][3] for k in range(3)) for i in range(3)]
    return [r[0] + [t[0]], r[1] + [t[1]], r[2] + [t[2]], [0, 0, 0, 1]]


def mul(a, b):
    return [[sum(a[i][k] * b[k][j] for k in range(4)) for j in range(4)] for i in range(4)]


def apply(m, p):
    return [sum(m[i][k] * p[k] for k in range(3)) + m[i][3] for i in range(3)]


rows = {}
for water, opts in waters.items():
    for seed in range(1, scenes + 1):
        d = os.path.join(out, f"stereo_enhance_{water.replace(' ', '_')}_{seed}")
        if not os.path.exists(os.path.join(d, "truth", "poses.json")):
            rc, log = run(["simulate-stereo", "--out", d, "--force", "--seed", str(seed), "--views", "3",
                           "--supersample", "1"] + opts.split())
            if rc:
                print(f"simulate-stereo {water} seed {seed} failed: {log}")
                continue
        truth = json.load(open(d + "/truth/poses.json"))
        points = [list(map(float, l.split(","))) for l in open(d + "/truth/check_points.csv").read().split("\n")[1:] if l]
        for mode in modes:
            model, pose = f"{d}/object_{mode}.json", f"{d}/pose_{mode}.json"
            rc, log = run(["stereo-model", "--calib", d + "/stereo.yaml", "--pairs", d + "/overview", "--out", model,
                           "--feature-enhance", mode])
            entry = {"found": False}
            if rc == 0:
                rc, log = run(["stereo-locate", "--calib", d + "/stereo.yaml", "--model", model, "--pairs",
                               d + "/approach", "--out", pose, "--feature-enhance", mode])
            if rc == 0:
                r = json.load(open(pose))
                v = r["views"][0] if r.get("views") else {}
                entry = {"found": r["found"], "stereo": v.get("stereo_points", 0), "inliers": v.get("inliers", 0),
                         "chain": r.get("feature_enhance", {}).get("chain", "none")}
                if r["found"]:
                    est = mul(truth["overview"]["ov_001"], r["object_from_camera"])
                    ie, it = inv(est), inv(truth["approach"][v["pair"]])
                    entry["error_mm"] = 1000 * statistics.mean(math.dist(apply(ie, p), apply(it, p)) for p in points)
            else:
                print(f"  {water} seed {seed} {mode}: failed: {log.strip()[-300:]}")
            rows.setdefault((water, mode), []).append(entry)
            print(f"  {water} seed {seed} {mode:<8} chain {entry.get('chain', '?'):<32} stereo points "
                  f"{entry.get('stereo', 0):5d}  model inliers {entry.get('inliers', 0):4d}  " +
                  (f"error {entry['error_mm']:.2f} mm" if "error_mm" in entry else "not found"), flush=True)

print("stereo enhance: water      | mode     found  stereo inliers/pair  model inliers  check-point error "
      "median / worst (mm)")
for (water, mode), entries in rows.items():
    ok = [e for e in entries if e.get("found")]
    errs = sorted(e["error_mm"] for e in ok)
    stereo = statistics.mean(e.get("stereo", 0) for e in entries)
    inl = statistics.mean(e.get("inliers", 0) for e in entries)
    err = f"{statistics.median(errs):6.2f} / {errs[-1]:6.2f}" if errs else "     - /      -"
    print(f"stereo enhance: {water:<10} | {mode:<8} {len(ok):>2}/{len(entries):<2} {stereo:12.0f} {inl:18.0f}"
          f"        {err}")
