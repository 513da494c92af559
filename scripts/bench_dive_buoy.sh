#!/usr/bin/env bash
# SeaMap's own trajectory on the Earth with a towed buoy (issue 30, part 4;
# docs/GEOREF.md "SeaMap's own trajectory on the Earth"): per survey seed, a
# drifting survey whose navigation is moved 36 m (no fix to trust), a buoy
# towed on a 4 m tether along the true path (the simulator's tractrix) with
# 0.4 m GPS noise at 1 Hz; `trajectory --mode vo --buoy` against `georef` on
# the same fixes with the exact keyframes (the truth). Prints one line per
# seed (horizontal RMSE of both, their ratio, the fit's scale) and the worst
# ratio against the issue's target (1.5x).
#   SEAMAP_BENCH_QUICK=1   one seed
#   SEAMAP_BIN=path        the seamap binary (default build/seamap, built by scripts/build.sh)
set -euo pipefail
root="$(cd "$(dirname "$0")/.." && pwd)"
seamap="${SEAMAP_BIN:-$root/build/seamap}"
[[ -x "$seamap" ]] || "$root/scripts/build.sh" >/dev/null
out="$root/out/bench/dive_buoy"
mkdir -p "$out"
seeds="6 7 8"
[[ "${SEAMAP_BENCH_QUICK:-0}" == 1 ]] && seeds="6"
noise="--nav-noise 0.005 --nav-drift 0.5 --heading-noise 0.5"
worst=0
for seed in $seeds; do
  dir="$out/seed$seed"
  [[ -f "$dir/survey/nav.csv" ]] || "$seamap" simulate --out "$dir/survey" --force --quiet --frames 160 \
    --line-length 8 --line-spacing 0.9 --sea-depth 5 --image-format jpg --seed "$seed" $noise >/dev/null
  # The moved navigation, the buoy's fixes, the depth log and the truth as TUM keyframes.
  python3 - "$dir" "$seed" <<'PY'
import csv, math, random, sys
d, seed = sys.argv[1], int(sys.argv[2])
lat0, lon0, tether, sigma = 43.1, 131.9, 4.0, 0.4
m_lat = 111132.954 - 559.822 * math.cos(2 * math.radians(lat0)) + 1.175 * math.cos(4 * math.radians(lat0))
m_lon = 111412.84 * math.cos(math.radians(lat0)) - 93.5 * math.cos(3 * math.radians(lat0))
nav = list(csv.DictReader(open(f"{d}/survey/nav.csv")))
with open(f"{d}/moved_nav.csv", "w", newline="") as f:
    w = csv.DictWriter(f, fieldnames=list(nav[0].keys()))
    w.writeheader()
    for r in nav:
        r["x_m"], r["y_m"] = f"{float(r['x_m']) + 30:.6f}", f"{float(r['y_m']) - 20:.6f}"
        w.writerow(r)
truth = [{k: (v if k == "image" else float(v)) for k, v in r.items()} for r in csv.DictReader(open(f"{d}/survey/nav_truth.csv"))]
reach = lambda depth: math.sqrt(max(tether * tether - depth * depth, 0))
h0 = math.radians(truth[0]["heading_deg"])
bx, by = truth[0]["x_m"] - reach(truth[0]["depth_m"]) * math.sin(h0), truth[0]["y_m"] - reach(truth[0]["depth_m"]) * math.cos(h0)
rng = random.Random(seed * 7919 + 7)
fixes, next_fix = [], 0.0
for a, b in zip(truth, truth[1:]):
    t = a["time_s"]
    while t < b["time_s"] - 1e-9:  # the vehicle linear between frames, 20 ms steps; the buoy pulled taut
        f = (t - a["time_s"]) / (b["time_s"] - a["time_s"])
        vx, vy = a["x_m"] + f * (b["x_m"] - a["x_m"]), a["y_m"] + f * (b["y_m"] - a["y_m"])
        r = reach(a["depth_m"] + f * (b["depth_m"] - a["depth_m"]))
        dist = math.hypot(vx - bx, vy - by)
        if dist > r:
            bx, by = vx - r * (vx - bx) / dist, vy - r * (vy - by) / dist
        if t >= next_fix - 1e-9:
            fixes.append((t, bx + rng.gauss(0, sigma), by + rng.gauss(0, sigma)))
            next_fix += 1.0
        t += 0.02
with open(f"{d}/buoy.csv", "w") as f:
    f.write("time_s,lat,lon\n")
    for t, x, y in fixes:
        f.write(f"{t:.3f},{lat0 + y / m_lat:.10f},{lon0 + x / m_lon:.10f}\n")
with open(f"{d}/depth.csv", "w") as f:
    f.write("time_s,depth_m\n" + "".join(f"{r['time_s']:.3f},{r['depth_m']:.4f}\n" for r in truth))
with open(f"{d}/truth.tum", "w") as f:
    f.write("".join(f"{r['time_s']:.6f} {r['x_m']:.6f} {r['y_m']:.6f} {-r['depth_m']:.6f} 0 0 0 1\n" for r in truth))
PY
  "$seamap" trajectory --mode vo --images "$dir/survey/photo" --nav "$dir/moved_nav.csv" \
    --camera "$dir/survey/camera.json" --origin 43.1,131.9 $noise --quiet --out "$dir/vo_earth.csv" \
    --buoy "$dir/buoy.csv" --tether-length 4 >"$dir/vo.log" 2>&1
  "$seamap" georef --keyframes "$dir/truth.tum" --buoy "$dir/buoy.csv" --tether-length 4 \
    --depth-csv "$dir/depth.csv" --out "$dir/exact_nav.csv" --quiet >"$dir/georef.log" 2>&1
  line=$(python3 - "$dir" <<'PY'
import csv, json, math, sys
d = sys.argv[1]
lat0, lon0 = 43.1, 131.9
m_lat = 111132.954 - 559.822 * math.cos(2 * math.radians(lat0)) + 1.175 * math.cos(4 * math.radians(lat0))
m_lon = 111412.84 * math.cos(math.radians(lat0)) - 93.5 * math.cos(3 * math.radians(lat0))
truth = {round(float(r["time_s"]), 3): (float(r["x_m"]), float(r["y_m"])) for r in csv.DictReader(open(f"{d}/survey/nav_truth.csv"))}
def rmse(path):
    e = [(((float(r["lon"]) - lon0) * m_lon - truth[round(float(r["time_s"]), 3)][0]) ** 2 +
          ((float(r["lat"]) - lat0) * m_lat - truth[round(float(r["time_s"]), 3)][1]) ** 2)
         for r in csv.DictReader(open(path))]
    return math.sqrt(sum(e) / len(e))
vo, exact = rmse(f"{d}/vo_earth.csv"), rmse(f"{d}/exact_nav.csv")
report = json.load(open(f"{d}/vo_earth.georef.json"))
print(f"{vo:.3f} {exact:.3f} {vo / exact:.2f} {report['scale']:.4f} {report['predicted_rmse_m']:.3f}")
PY
)
  read -r vo exact ratio scale predicted <<<"$line"
  printf "dive buoy seed %s: vo+buoy %.3f m, georef exact keyframes %.3f m, ratio %.2f (target <= 1.5), scale %s, predicted %s m\n" \
    "$seed" "$vo" "$exact" "$ratio" "$scale" "$predicted"
  worst=$(python3 -c "print(max($worst, $ratio))")
done
echo "dive buoy worst ratio: $worst (target <= 1.5)"
