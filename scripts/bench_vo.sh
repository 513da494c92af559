#!/usr/bin/env bash
# Visual odometry on relief and in murky water (issue 29, docs/TERRAIN.md
# "Visual odometry on relief"). Prints one line per figure:
#  - `trajectory --mode vo` drift on the issue's surveys (14 m lanes 0.9 m
#    apart, 720 frames, JPEG, navigation drifting 0.5 m/min, 5 mm noise, 0.5
#    degree heading noise): flat; relief 0.15 m rms; relief 0.15 m with pitch
#    and roll +-3 degrees and --degrade --color; median and worst of 3 seeds,
#    the target beside it;
#  - seed 004's Table 4 in its form: the absolute trajectory error (max, mean,
#    median, min, rmse, sse, std in metres) without and with the enhancement
#    chain in front of the features, on degraded surveys.
#   SEAMAP_BENCH_QUICK=1   240 frames, one seed, one Table 4 survey
#   SEAMAP_BIN=path        the seamap binary (default build/seamap, built by scripts/build.sh)
set -euo pipefail
root="$(cd "$(dirname "$0")/.." && pwd)"
seamap="${SEAMAP_BIN:-$root/build/seamap}"
[[ -x "$seamap" ]] || "$root/scripts/build.sh" >/dev/null
out="$root/out/bench/vo"
mkdir -p "$out"
frames=720; seeds="1 2 3"
[[ "${SEAMAP_BENCH_QUICK:-0}" == 1 ]] && { frames=240; seeds="1"; }
base="--frames $frames --image-format jpg --line-length 14 --line-spacing 0.9 --nav-drift 0.5 --nav-noise 0.005 --heading-noise 0.5"
noise="--nav-noise 0.005 --nav-drift 0.5 --heading-noise 0.5"

simulate() {  # name, extra simulate args
  local dir="$out/$1"
  if [[ ! -f "$dir/nav.csv" ]] || [[ "$(($(wc -l <"$dir/nav.csv") - 1))" != "$frames" ]]; then
    "$seamap" simulate --out "$dir" --force --quiet $base $2 >/dev/null 2>&1
  fi
}

vo() {  # survey name, run name, extra trajectory args; writes $out/runs/<run>.{csv,json,eval.json}
  local dir="$out/$1" run="$out/runs/$2"
  mkdir -p "$out/runs"
  "$seamap" trajectory --mode vo --images "$dir/photo" --nav "$dir/nav.csv" --camera "$dir/camera.json" \
    --origin 43.1,131.9 --quiet $noise --out "$run.csv" --report "$run.json" ${3:-} >/dev/null 2>"$run.log"
  "$seamap" trajectory-eval "$run.csv" "$dir/nav_truth.csv" --origin 43.1,131.9 --json "$run.eval.json" >/dev/null 2>&1
}

drift_line() {  # label, target text, run names...
  local label="$1" target="$2"
  shift 2
  python3 - "$label" "$target" "$out/runs" "$@" <<'PY'
import json, sys
label, target, runs, names = sys.argv[1], sys.argv[2], sys.argv[3], sys.argv[4:]
d = sorted(json.load(open(f"{runs}/{n}.eval.json"))["drift_percent"] for n in names)
a = sorted(json.load(open(f"{runs}/{n}.eval.json"))["ate_m"] * 1000 for n in names)
r = [json.load(open(f"{runs}/{n}.json")) for n in names]
models = f"{sum(x['homography'] for x in r)} H / {sum(x['essential'] for x in r)} E / {sum(x['failed_pairs'] for x in r)} failed pairs"
print(f"vo drift, {label:<44} median {d[len(d) // 2]:.3f} %  worst {d[-1]:.3f} %  (ATE median {a[len(a) // 2]:.0f} mm; "
      f"{len(d)} seeds; {models})  target {target}")
PY
}

# 1. Drift over three seeds.
for seed in $seeds; do
  simulate "flat_$seed" "--seed $seed"
  simulate "relief_$seed" "--seed $seed --relief 0.15"
  simulate "rough_$seed" "--seed $seed --relief 0.15 --pitch-amp 3 --roll-amp 3 --degrade --color"
  for s in flat relief rough; do vo "${s}_$seed" "${s}_$seed"; done
  vo "rough_$seed" "rough_auto_$seed" "--feature-enhance auto"
done
runs() { for seed in $seeds; do echo -n "$1_$seed "; done; }
drift_line "flat" "0.15 % (as before)" $(runs flat)
drift_line "relief 0.15 m rms" "<= 0.5 %" $(runs relief)
drift_line "relief 0.15 + pitch/roll 3 + degrade + color" "<= 0.5 % (seed 003: 1.3 %)" $(runs rough)
drift_line "the same, --feature-enhance auto" "<= 0.5 %" $(runs rough_auto)

# 2. Seed 004's Table 4: APE without and with enhancement, one seed, several
# degradations (relief 0.15 m, pitch/roll 3 degrees throughout).
table4() {  # label, survey name, simulate args (none: the survey exists)
  [[ -n "${3:-}" ]] && simulate "$2" "--seed 1 --relief 0.15 --pitch-amp 3 --roll-amp 3 $3"
  vo "$2" "$2_off"
  vo "$2" "$2_auto" "--feature-enhance auto"
  vo "$2" "$2_default" "--feature-enhance default"
  python3 - "$1" "$out/$2/nav_truth.csv" "$out/runs/$2" <<'PY'
import csv, json, math, statistics, sys
label, truth_path, run = sys.argv[1:4]
truth = {r["image"]: (float(r["x_m"]), float(r["y_m"])) for r in csv.DictReader(open(truth_path))}
def ape(path):
    e = []
    for r in csv.DictReader(open(path)):
        t = truth.get(r["image"])
        if t: e.append(math.hypot(float(r["x_m"]) - t[0], float(r["y_m"]) - t[1]))
    return e
for variant in ("off", "auto", "default"):
    e = ape(f"{run}_{variant}.csv")
    rep = json.load(open(f"{run}_{variant}.json"))
    chain = rep.get("feature_enhance", {}).get("chain", "none")
    sse = sum(x * x for x in e)
    print(f"table 4, {label:<30} {variant:<8} chain {chain:<32} APE m: max {max(e):.4f} mean {statistics.mean(e):.4f} "
          f"median {statistics.median(e):.4f} min {min(e):.4f} rmse {math.sqrt(sse / len(e)):.4f} sse {sse:.3f} "
          f"std {statistics.pstdev(e):.4f}  drift {json.load(open(run + '_' + variant + '.eval.json'))['drift_percent']:.3f} %")
PY
}
table4 "degrade + color" rough_1  # the survey above
if [[ "${SEAMAP_BENCH_QUICK:-0}" != 1 ]]; then
  table4 "degrade (gray)" t4_degrade "--degrade"
  table4 "degrade + color + haze 0.8 + noise 4" t4_haze "--degrade --color --haze 0.8 --noise 4"
fi
