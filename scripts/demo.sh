#!/usr/bin/env bash
# The main job on the embedded sample: a live replay of a survey. The map is
# built while the server and operator console show it growing at the printed
# URL. Ctrl-C stops it; the mission stays in out/demo/mission.mbtiles.
#   SEAMAP_DEMO_SPEED=4 scripts/demo.sh     replay 4x faster than recorded (default 2)
#   SEAMAP_PORT=8080                         port to serve on
set -euo pipefail
root="$(cd "$(dirname "$0")/.." && pwd)"
build="${SEAMAP_BUILD_DIR:-$root/build}"
out="$root/out/demo"
"$root/scripts/setup.sh"
"$root/scripts/build.sh"
seamap="$build/seamap"

if [[ ! -f "$out/survey/nav.csv" ]]; then
  echo "demo: rendering the sample survey (seamap simulate)"
  "$seamap" simulate --out "$out/survey" --force
fi
echo "demo: replaying $out/survey live; open the URL below in a browser (Ctrl-C to stop)"
exec "$seamap" replay "$out/survey" --speed "${SEAMAP_DEMO_SPEED:-2}" \
  --config "$root/config/default.json" --out "$out/mission.mbtiles" --overwrite \
  --port "${SEAMAP_PORT:-8080}"
