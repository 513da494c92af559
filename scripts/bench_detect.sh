#!/usr/bin/env bash
# The recogniser's figures (docs/DETECT.md): the shipped model on two surveys training never saw (seeds 1 and 2,
# gray and degraded colour, 1200 frames, 30 objects each), built with --detect (the live worker: searches, ms per
# window, backlog), then `seamap detect` on the finished maps, scored pooled by scripts/eval_detections.py
# (same class within 10 cm). Called by scripts/bench.sh; alone: scripts/bench_detect.sh build/seamap OUT_DIR
set -euo pipefail
seamap="$1" out="$2"
root="$(cd "$(dirname "$0")/.." && pwd)"
[[ -f "$root/data/models/seabed_objects.onnx" ]] || { echo "detect: no data/models/seabed_objects.onnx"; exit 0; }
mkdir -p "$out"
pairs=()
for seed in 1 2; do
  s="$out/objects_$seed"
  extra=()
  [[ $seed == 2 ]] && extra=(--color --degrade)
  "$seamap" simulate --quiet --out "$s" --objects 30 --frames 1200 --seed $seed --force "${extra[@]}" >/dev/null
  origin="$(python3 -c 'import json,sys; print(",".join(map(str, json.load(open(sys.argv[1]))["origin"])))' "$s/survey.json")"
  "$seamap" build --quiet --images "$s/photo" --nav "$s/nav.csv" --camera "$s/camera.json" --origin "$origin" \
    --out "$s.mbtiles" --overwrite --detect | sed -n "s/^detect: /detect (build --detect, seed $seed): /p" |
    awk -v seed=$seed '{print}
      /windows searched/ {for (i = 1; i < NF; i++) {if ($(i+1) == "windows") n = $i; if ($(i+1) == "ms") ms = $i}
        printf "detect (build --detect, seed %s): %d searches x %.1f ms = %.1f s of one core per 240 s of survey at 5 frames/s\n", seed, n, ms, n * ms / 1000}'
  "$seamap" detect --quiet "$s.mbtiles" --out "$s.geojson" | sed -n "s/^/detect (seamap detect, seed $seed): /p"
  pairs+=("$s.geojson" "$s/truth/objects.csv")
done
python3 "$root/scripts/eval_detections.py" "${pairs[@]}" | sed 's/^/detect (seeds 1+2, 60 objects): /'
