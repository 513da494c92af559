#!/usr/bin/env bash
# The main job on the embedded sample: simulate a survey, then build its photo map.
set -euo pipefail
root="$(cd "$(dirname "$0")/.." && pwd)"
build="${SEAMAP_BUILD_DIR:-$root/build}"
out="$root/out/demo"
"$root/scripts/setup.sh"
"$root/scripts/build.sh"
seamap="$build/seamap"

if [[ ! -f "$out/survey/nav.csv" ]]; then
  "$seamap" simulate --out "$out/survey" --force
fi
"$seamap" build --images "$out/survey/photo" --nav "$out/survey/nav.csv" \
  --camera "$out/survey/camera.json" --origin 43.1,131.9 \
  --config "$root/config/default.json" --out "$out/mission.mbtiles" --overwrite
"$seamap" info "$out/mission.mbtiles"
echo
echo "demo: map at $out/mission.mbtiles (open it in QGIS, or serve it once 'seamap serve' lands)"
