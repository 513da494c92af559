#!/usr/bin/env bash
# The recogniser's figures (docs/DETECT.md): the shipped model on two surveys training never saw (seeds 1 and 2,
# gray and degraded colour, 1200 frames, 30 objects each), built with --detect (the live worker: searches, ms per
# window, backlog), then `seamap detect` on the finished maps, scored pooled by scripts/eval_detections.py
# (same class within 10 cm). Called by scripts/bench.sh; alone: scripts/bench_detect.sh build/seamap OUT_DIR
# Then the stress bench (issue 32): one held-out survey per condition (clear, murky --degrade, altitude 3.5 m,
# JPEG 50 photos, motion blur, half-buried --bury 0.5, --clutter look-alikes; seeds 3101-3107, never used in
# training or validation), `seamap detect` on each, recall / precision / median error per class and condition,
# pooled, and the worst condition. DETECT_ARGS (e.g. "--model new.onnx", "--keep-cut-views") go to
# `seamap detect`; STRESS_ONLY=1 skips the seeds 1+2 part, STRESS=0 the stress part; STRESS_FRAMES (600) and
# STRESS_OBJECTS (20) size the surveys; STRESS_CONDITIONS picks some (also altitude_1m and altitude_4m, seeds 3108
# and 3109, not in the default seven); STRESS_REUSE=1 searches the maps of an earlier run again instead of
# simulating them. KEEP_CUT=0 skips the --keep-cut-views search; DIAGNOSE=1 also searches each map at
# --min-score 0.1 and says why each object was missed and what each false detection lay on
# (scripts/diagnose_detections.py, written to stress_CONDITION.diagnosis). Two runs (another model on the same maps:
# STRESS_REUSE=1 DETECT_ARGS="--model M") side by side: scripts/compare_detect_benches.py OUT_BEFORE OUT_AFTER.
set -euo pipefail
seamap="$1" out="$2"
read -r -a detect_args <<<"${DETECT_ARGS:-}"
root="$(cd "$(dirname "$0")/.." && pwd)"
[[ -f "$root/data/models/seabed_objects.onnx" ]] || { echo "detect: no data/models/seabed_objects.onnx"; exit 0; }
mkdir -p "$out"
origin_of() { python3 -c 'import json,sys; print(",".join(map(str, json.load(open(sys.argv[1]))["origin"])))' "$1"; }
if [[ "${STRESS_ONLY:-0}" != 1 ]]; then
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
fi
[[ "${STRESS:-1}" == 1 ]] || exit 0

# ---- stress: one held-out survey per condition
frames="${STRESS_FRAMES:-600}" objects="${STRESS_OBJECTS:-20}"
read -r -a conditions <<<"${STRESS_CONDITIONS:-clear murky altitude_3.5m jpeg_50 blur half_buried clutter}"
declare -A extra=(
  [clear]="" [murky]="--degrade" [altitude_3.5m]="--altitude-min 3.3 --altitude-max 3.7"
  [jpeg_50]="--image-format jpg --jpeg-quality 50" [blur]="--blur 4" [half_buried]="--bury 0.5" [clutter]="--clutter 12"
  [altitude_1m]="--altitude-min 0.9 --altitude-max 1.1" [altitude_4m]="--altitude-min 3.8 --altitude-max 4.2")
declare -A seeds=([clear]=3101 [murky]=3102 [altitude_3.5m]=3103 [jpeg_50]=3104 [blur]=3105 [half_buried]=3106
  [clutter]=3107 [altitude_1m]=3108 [altitude_4m]=3109)
all_pairs=() keep_pairs=()
for c in "${conditions[@]}"; do
  seed=${seeds[$c]} s="$out/stress_$c"
  read -r -a opts <<<"${extra[$c]}"
  if [[ "${STRESS_REUSE:-0}" == 1 && -f "$s.mbtiles" ]]; then :  # the survey of an earlier run (other DETECT_ARGS)
  elif ! "$seamap" simulate --quiet --out "$s" --objects "$objects" --frames "$frames" --seed $seed --color --force \
    "${opts[@]}" >/dev/null 2>&1; then  # that many do not fit 1 m apart on this seed's path
    "$seamap" simulate --quiet --out "$s" --objects $((objects * 3 / 4)) --frames "$frames" --seed $seed --color \
      --force "${opts[@]}" >/dev/null
  fi
  [[ "${STRESS_REUSE:-0}" == 1 && -f "$s.mbtiles" ]] ||
    "$seamap" build --quiet --images "$s/photo" --nav "$s/nav.csv" --camera "$s/camera.json" \
      --origin "$(origin_of "$s/survey.json")" --out "$s.mbtiles" --overwrite >/dev/null
  "$seamap" detect --quiet "$s.mbtiles" --out "$s.geojson" "${detect_args[@]}" >/dev/null
  python3 "$root/scripts/eval_detections.py" "$s.geojson" "$s/truth/objects.csv" | tee "$s.eval" |
    sed "s/^/detect stress ($c, seed $seed): /"
  all_pairs+=("$s.geojson" "$s/truth/objects.csv")
  if [[ "${DIAGNOSE:-0}" == 1 ]]; then
    "$seamap" detect --quiet "$s.mbtiles" --out "$s.low.geojson" "${detect_args[@]}" --min-score 0.1 >/dev/null
    python3 "$root/scripts/diagnose_detections.py" "$s.geojson" "$s.low.geojson" "$s/truth/objects.json" \
      >"$s.diagnosis"
    tail -1 "$s.diagnosis" | sed "s/^/detect stress ($c, seed $seed): diagnosis /"
  fi
  [[ "${KEEP_CUT:-1}" == 1 ]] || continue
  # The class-aware level rule's effect: the same search keeping the cut views (level_rule.h).
  "$seamap" detect --quiet "$s.mbtiles" --out "$s.keep.geojson" --keep-cut-views "${detect_args[@]}" >/dev/null
  keep_pairs+=("$s.keep.geojson" "$s/truth/objects.csv")
done
python3 "$root/scripts/eval_detections.py" "${all_pairs[@]}" | sed 's/^/detect stress (pooled): /'
[[ ${#keep_pairs[@]} -eq 0 ]] ||
  python3 "$root/scripts/eval_detections.py" "${keep_pairs[@]}" | grep -E '^(class|anchor|all) ' |
  sed 's/^/detect stress (pooled, --keep-cut-views: before the level rule): /'
for c in "${conditions[@]}"; do
  awk -v c=$c '$1 == "all" {print c, $5, $6, $7}' "$out/stress_$c.eval"
done | sort -k2,2g | awk 'NR == 1 {printf "detect stress (worst condition by recall): %s recall %s precision %s median %s cm\n", $1, $2, $3, $4}'
for c in "${conditions[@]}"; do
  awk -v c=$c '$1 == "all" {print c, $5, $6, $7}' "$out/stress_$c.eval"
done | sort -k3,3g | awk 'NR == 1 {printf "detect stress (worst condition by precision): %s recall %s precision %s median %s cm\n", $1, $2, $3, $4}'
