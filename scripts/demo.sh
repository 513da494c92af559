#!/usr/bin/env bash
# The demo is the mission: a dive replayed live, with what makes SeaMap
# different switched on. Rendered once (cached in out/demo/dive/): a survey
# whose navigation drifts, over a seabed with relief, objects and murky water,
# crossing a subsea structure four times, and a stereo rig's pairs of that
# structure. The replay places the frames with the online filter (--nav-mode
# ekf), paints the raw and enhanced maps (config/demo_dive.json), searches the tiles for objects
# (--detect) and locates the structure in the stereo pairs (--stereo) as the
# dive goes; the server and operator console show it at the printed URL.
# Ctrl-C stops it; the mission stays in out/demo/mission.mbtiles.
#   SEAMAP_DEMO_SPEED=4 scripts/demo.sh     replay 4x faster than recorded (default 2)
#   SEAMAP_PORT=8080                         port to serve on
set -euo pipefail
root="$(cd "$(dirname "$0")/.." && pwd)"
build="${SEAMAP_BUILD_DIR:-$root/build}"
out="$root/out/demo"
dive="$out/dive"
"$root/scripts/setup.sh"
"$root/scripts/build.sh"
seamap="$build/seamap"

if [[ ! -f "$dive/ready" ]]; then
  echo "demo: rendering the dive once (seamap simulate-stereo, stereo-model, simulate): a few minutes"
  rm -rf "$dive" && mkdir -p "$dive"
  # The structure and a stereo rig's passes over it (dive/: a pair each, named by its time).
  "$seamap" simulate-stereo --out "$dive/wellhead" --seed 2 --views 2 --dive 4 --supersample 1
  "$seamap" stereo-model --calib "$dive/wellhead/stereo.yaml" --pairs "$dive/wellhead/overview" \
    --out "$dive/wellhead.json"
  # The survey flies through the stereo passes (waypoints), so each pair is taken where and when
  # the survey's vehicle is: path.csv, the pairs' times on the survey's clock (pair_times.csv)
  # and the simulate options that match the passes' altitude (simulate.args).
  python3 - "$dive" <<'PY'
import csv, json, math, sys
dive = sys.argv[1]
lat0, lon0 = 43.1, 131.9  # simulate-stereo's dive origin, simulate's default origin
m_lat = 111132.954 - 559.822 * math.cos(2 * math.radians(lat0)) + 1.175 * math.cos(4 * math.radians(lat0))
m_lon = 111412.84 * math.cos(math.radians(lat0)) - 93.5 * math.cos(3 * math.radians(lat0))
rows = list(csv.DictReader(open(f"{dive}/wellhead/dive/nav.csv")))
legs = [rows[i:i + 11] for i in range(0, len(rows), 11)]  # 11 rows a pass, the pair at the middle
xy = lambda r: ((float(r["lon"]) - lon0) * m_lon, (float(r["lat"]) - lat0) * m_lat)
speed = 0.5  # simulate's default, the passes' own
points, s, times = [(-6.0, -8.0)], 0.0, []
for leg in legs:
    for r in (leg[0], leg[-1]):
        p = xy(r)
        s += math.dist(points[-1], p)
        points.append(p)
    times.append(s - math.dist(xy(leg[5]), points[-1]))  # arc length at the pair
points.append((points[-1][0] + 4, points[-1][1]))
s += 4
with open(f"{dive}/path.csv", "w") as f:
    f.write("x_m,y_m\n" + "".join(f"{x:.4f},{y:.4f}\n" for x, y in points))
truth = json.load(open(f"{dive}/wellhead/truth/dive.json"))
with open(f"{dive}/pair_times.csv", "w") as f:
    f.write("image,time_s\n")
    for k, sighting in enumerate(truth["sightings"]):  # the last: after the survey ends (skipped)
        t = times[k] / speed if k < len(times) else s / speed + 30
        f.write(f"{sighting['pair']},{t:.3f}\n")
altitude = sum(float(leg[5]["altitude_m"]) for leg in legs) / len(legs)
frames = int(s / speed * 5) + 1
open(f"{dive}/simulate.args", "w").write(
    f"--frames {frames} --altitude-min {altitude - 0.05:.3f} --altitude-max {altitude + 0.05:.3f} "
    f"--sea-depth {truth['seabed_depth_m']} --pitch-amp 0 --roll-amp 0")
PY
  # Drifting navigation, objects on a seabed with relief, murky water, colour.
  # shellcheck disable=SC2046
  "$seamap" simulate --out "$dive/survey" --path "$dive/path.csv" $(cat "$dive/simulate.args") \
    --nav-drift 0.5 --nav-noise 0.005 --heading-noise 0.5 --objects 8 --relief 0.12 --degrade --color --quiet
  touch "$dive/ready"
fi
echo "demo: replaying the dive live; open the URL below in a browser (Ctrl-C to stop)"
# --refine-nav corrects the map as passes cross (and refines the whole dive at its end).
exec "$seamap" replay "$dive/survey" --speed "${SEAMAP_DEMO_SPEED:-2}" \
  --config "$root/config/demo_dive.json" --out "$out/mission.mbtiles" --overwrite \
  --nav-mode ekf --refine-nav --detect \
  --stereo "$dive/wellhead/dive" --pair-times "$dive/pair_times.csv" \
  --calib "$dive/wellhead/stereo.yaml" --model "$dive/wellhead.json" --rig down \
  --port "${SEAMAP_PORT:-8080}"
