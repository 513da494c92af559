#!/usr/bin/env bash
# Issue 32's new-class target, end to end on the CPU: two simulated missions with drums (a class the shipped
# model does not know; seeds 3201 and 3202, 15 drums among 30 objects), the first reviewed from its
# truth (every object confirmed or marked with its box) and turned into training data (`seamap training-data`),
# the shipped model fine-tuned on it (scripts/train_detector.py --from-missions, MINUTES of wall time and at
# most 2 x MINUTES CPU-minutes), then `seamap detect` with the new model on the second, unseen mission (drums:
# recall and precision >= 0.8), and on two held-out surveys of the old classes with the shipped and the new
# model (old classes may lose at most 0.03 of recall).
#   scripts/bench_new_class.sh build/seamap OUT_DIR [MINUTES (15)] [CPU_MINUTES (the whole budget when given)]
# FINETUNE_ARGS (e.g. "--lr 2e-3") go to train_detector.py. An earlier run's missions, training data and replay
# surveys in OUT_DIR are used again.
set -euo pipefail
read -r -a finetune_args <<<"${FINETUNE_ARGS:-}"
seamap="$1" out="$2" minutes="${3:-15}"
# Without CPU_MINUTES the fine-tune stops at MINUTES of wall time or 2 x MINUTES CPU-minutes, whichever first.
cpu_args=()
[[ -n "${4:-}" ]] && cpu_args=(--cpu-minutes "$4")
root="$(cd "$(dirname "$0")/.." && pwd)"
mkdir -p "$out"
# Half the objects are drums (--object-classes takes each class once, in turn): drums among tyres in the
# reviewed mission, among crates (boxes of a lying drum's size) in the unseen one.
origin_of() { python3 -c 'import json,sys; print(",".join(map(str, json.load(open(sys.argv[1]))["origin"])))' "$1"; }

mission() {  # seed dir classes: simulate (30 objects, fewer when they do not fit) and build
  local seed=$1 s=$2 classes=$3 n
  if [[ ! -f "$s.mbtiles" && ! -f "$s/truth/objects.csv" ]]; then  # (a survey of an earlier run is built again)
    for n in 30 26 22; do
      "$seamap" simulate --quiet --out "$s" --objects $n --object-classes $classes --frames 1200 --seed "$seed" \
        --color --force >/dev/null 2>&1 && break
    done
  fi
  if [[ ! -f "$s.mbtiles" ]]; then
    "$seamap" build --quiet --images "$s/photo" --nav "$s/nav.csv" --camera "$s/camera.json" \
      --origin "$(origin_of "$s/survey.json")" --out "$s.tmp.mbtiles" --overwrite >/dev/null
    mv "$s.tmp.mbtiles" "$s.mbtiles"
  fi
  echo "new class: mission $(basename "$s") (seed $seed): $(($(wc -l <"$s/truth/objects.csv") - 1)) objects," \
    "$(grep -c '^drum,' "$s/truth/objects.csv") drums"
}
mission 3201 "$out/mission_a" drum,tyre
mission 3202 "$out/mission_b" drum,crate

# The operator's review of mission A from its truth: the shipped model's search, `seamap review --truth`
# (confirm, reject, box the missed drums), `seamap training-data`. TRUTH_WINDOWS=1 (or a seamap without
# `review`) writes the truth straight into the same layout instead (scripts/truth_training_data.py).
if [[ ! -f "$out/training_a/manifest.json" ]]; then
  if [[ "${TRUTH_WINDOWS:-0}" != 1 ]] && "$seamap" review --help >/dev/null 2>&1; then
    "$seamap" detect --quiet "$out/mission_a.mbtiles" >/dev/null
    "$seamap" review "$out/mission_a.mbtiles" --truth "$out/mission_a" | sed 's/^/new class: review: /'
    "$seamap" training-data "$out/mission_a.mbtiles" --out "$out/training_a" | sed 's/^/new class: training data: /'
  else
    "$root/scripts/truth_training_data.py" "$out/mission_a" "$out/mission_a.mbtiles" "$out/training_a" |
      sed 's/^/new class: training data /'
  fi
fi

# Fine-tune (CPU time and peak memory measured; the machine may be shared, so CPU time is the cost).
/usr/bin/time -v -o "$out/finetune.time" "$root/scripts/train_detector.py" --from-missions "$out/training_a" \
  --base "$root/data/models/seabed_objects.onnx" --minutes "$minutes" "${cpu_args[@]}" \
  --seamap "$seamap" --work "$out/work" --replay-surveys 3 --out "$out/new.onnx" "${finetune_args[@]}" \
  >"$out/finetune.log" 2>&1 ||
  { tail -20 "$out/finetune.log"; exit 1; }
python3 - "$out/finetune.time" "$out/new.report.json" <<'PY'
import json, re, sys
t = open(sys.argv[1]).read()
cpu = float(re.search(r"User time \(seconds\): ([\d.]+)", t)[1]) + float(re.search(r"System time \(seconds\): ([\d.]+)", t)[1])
rss = int(re.search(r"Maximum resident set size \(kbytes\): (\d+)", t)[1]) / 1024
r = json.load(open(sys.argv[2]))
print(f"new class: fine-tune {r['steps']} steps in {r['train_minutes']} min of training, {cpu / 60:.1f} CPU-min in all "
      f"(data, training, export), peak RSS {rss:.0f} MB; validated min score {r['min_score']}")
for name, v in r.get("class_validation", r["validation"]).items():
    if v["truths"]:
        print(f"new class: held-out ground of mission_a, {name}: {v['found']}/{v['truths']} found, {v['false']} false"
              f" at its threshold {r.get('class_min_scores', {}).get(name, r['min_score'])}")
print(f"new class: per-class thresholds {json.dumps(r.get('class_min_scores', {}))}; hard negatives mined "
      f"(fraction, found, on simulated windows): {r.get('mined', [])}")
PY

# The unseen mission B with the new model: the drums.
"$seamap" detect --quiet "$out/mission_b.mbtiles" --model "$out/new.onnx" --out "$out/mission_b.new.geojson" |
  sed 's/^/new class: mission_b, new model: /'
python3 "$root/scripts/eval_detections.py" "$out/mission_b.new.geojson" "$out/mission_b/truth/objects.csv" |
  sed 's/^/new class: mission_b (unseen), new model: /'

# The old classes on held-out surveys (the stress bench's clear and murky seeds): shipped vs new model.
for seed in 3101 3102; do
  s="$out/old_$seed"
  if [[ ! -f "$s.mbtiles" ]]; then
    extra=()
    [[ $seed == 3102 ]] && extra=(--degrade)
    "$seamap" simulate --quiet --out "$s" --objects 20 --frames 600 --seed $seed --color --force "${extra[@]}" \
      >/dev/null 2>&1 ||
      "$seamap" simulate --quiet --out "$s" --objects 15 --frames 600 --seed $seed --color --force "${extra[@]}" \
        >/dev/null
    "$seamap" build --quiet --images "$s/photo" --nav "$s/nav.csv" --camera "$s/camera.json" \
      --origin "$(origin_of "$s/survey.json")" --out "$s.tmp.mbtiles" --overwrite >/dev/null
    mv "$s.tmp.mbtiles" "$s.mbtiles"
  fi
  "$seamap" detect --quiet "$s.mbtiles" --out "$s.shipped.geojson" >/dev/null
  "$seamap" detect --quiet "$s.mbtiles" --model "$out/new.onnx" --out "$s.new.geojson" >/dev/null
done
python3 "$root/scripts/eval_detections.py" "$out/old_3101.shipped.geojson" "$out/old_3101/truth/objects.csv" \
  "$out/old_3102.shipped.geojson" "$out/old_3102/truth/objects.csv" | tee "$out/old.shipped.eval" |
  sed 's/^/new class: old classes (seeds 3101+3102), shipped model: /'
python3 "$root/scripts/eval_detections.py" "$out/old_3101.new.geojson" "$out/old_3101/truth/objects.csv" \
  "$out/old_3102.new.geojson" "$out/old_3102/truth/objects.csv" | tee "$out/old.new.eval" |
  sed 's/^/new class: old classes (seeds 3101+3102), new model: /'
awk '$1 == "all" {r[FILENAME] = $5} END {printf "new class: old classes recall shipped %.2f, new %.2f: change %+.2f (allowed -0.03)\n", r[ARGV[1]], r[ARGV[2]], r[ARGV[2]] - r[ARGV[1]]}' \
  "$out/old.shipped.eval" "$out/old.new.eval"
