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
#   SEAMAP_BENCH_VO_PARTS="drift table4"   which parts run (Table 4 alone
#                          makes the surveys and raw/auto runs it lacks)
#   SEAMAP_BENCH_SEEDS="1 2 3"      seeds of the drift surveys and of Table 4's colour ones ("": none)
#   SEAMAP_BENCH_TABLE4_SEEDS="1"   seeds of Table 4's gray and haze surveys
#   SEAMAP_BENCH_VO_KEEP=1  Table 4 keeps the runs it finds (to add surveys to a table)
#   SEAMAP_BIN=path        the seamap binary (default build/seamap, built by scripts/build.sh)
set -euo pipefail
root="$(cd "$(dirname "$0")/.." && pwd)"
seamap="${SEAMAP_BIN:-$root/build/seamap}"
[[ -x "$seamap" ]] || "$root/scripts/build.sh" >/dev/null
out="$root/out/bench/vo"
mkdir -p "$out"
frames=720; seeds=${SEAMAP_BENCH_SEEDS-"1 2 3"}
[[ "${SEAMAP_BENCH_QUICK:-0}" == 1 ]] && { frames=240; seeds="1"; }
parts=${SEAMAP_BENCH_VO_PARTS:-"drift table4"}
t4_seeds=${SEAMAP_BENCH_TABLE4_SEEDS:-1}
rough="--relief 0.15 --pitch-amp 3 --roll-amp 3 --degrade --color"
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
if [[ " $parts " == *" drift "* ]]; then
  for seed in $seeds; do
    simulate "flat_$seed" "--seed $seed"
    simulate "relief_$seed" "--seed $seed --relief 0.15"
    simulate "rough_$seed" "--seed $seed $rough"
    for s in flat relief; do vo "${s}_$seed" "${s}_$seed"; done
    vo "rough_$seed" "rough_${seed}_off"
    vo "rough_$seed" "rough_${seed}_auto" "--feature-enhance auto"
  done
  runs() { for seed in $seeds; do echo -n "$1_$seed$2 "; done; }
  drift_line "flat" "0.15 % (as before)" $(runs flat)
  drift_line "relief 0.15 m rms" "<= 0.5 %" $(runs relief)
  drift_line "relief 0.15 + pitch/roll 3 + degrade + color" "<= 0.5 % (seed 003: 1.3 %)" $(runs rough _off)
  drift_line "the same, --feature-enhance auto" "<= 0.5 %" $(runs rough _auto)
fi
[[ " $parts " == *" table4 "* ]] || exit 0

# 2. Seed 004's Table 4: the absolute trajectory error without and with the
# enhancement chain in front of the features, on degraded surveys (relief
# 0.15 m, pitch/roll 3 degrees throughout). Per survey, Table 4's rows (APE
# max, mean, median, min, rmse, sse, std in metres) plus drift and the mean
# inliers per VO motion, columns raw / `auto` / `default`; then one summary
# line per survey.
table4() {  # survey name, simulate args; the raw and auto runs part 1 made are kept
  local keep=${SEAMAP_BENCH_VO_KEEP:-0}
  simulate "$1" "$2"
  [[ -f "$out/runs/$1_off.eval.json" ]] || vo "$1" "$1_off"
  [[ -f "$out/runs/$1_auto.eval.json" ]] || vo "$1" "$1_auto" "--feature-enhance auto"
  [[ "$keep" == 1 && -f "$out/runs/$1_default.eval.json" ]] || vo "$1" "$1_default" "--feature-enhance default"
}
table4_print() {  # "label=survey" ...
  python3 - "$out" "$@" <<'PY'
import csv, json, math, statistics, sys
out, surveys = sys.argv[1], [a.split("=", 1) for a in sys.argv[2:]]
variants = ("off", "auto", "default")
def ape(truth_path, path):
    truth = {r["image"]: (float(r["x_m"]), float(r["y_m"])) for r in csv.DictReader(open(truth_path))}
    e = []
    for r in csv.DictReader(open(path)):
        t = truth.get(r["image"])
        if t: e.append(math.hypot(float(r["x_m"]) - t[0], float(r["y_m"]) - t[1]))
    return e
summary = []
for label, name in surveys:
    cols = {}
    for v in variants:
        run = f"{out}/runs/{name}_{v}"
        e = ape(f"{out}/{name}/nav_truth.csv", run + ".csv")
        rep, ev = json.load(open(run + ".json")), json.load(open(run + ".eval.json"))
        sse = sum(x * x for x in e)
        cols[v] = {"max": max(e), "mean": statistics.mean(e), "median": statistics.median(e), "min": min(e),
                   "rmse": math.sqrt(sse / len(e)), "sse": sse, "std": statistics.pstdev(e),
                   "drift %": ev["drift_percent"], "inliers": rep.get("mean_motion_inliers", float("nan")),
                   "chain": rep.get("feature_enhance", {}).get("chain", "none")}
    print(f"table 4, {label} ({name}): APE in m; columns raw | auto ({cols['auto']['chain']}) | default")
    for row in ("max", "mean", "median", "min", "rmse", "sse", "std", "drift %", "inliers"):
        fmt = "{:10.1f}" if row == "inliers" else "{:10.3f}" if row in ("sse", "drift %") else "{:10.4f}"
        print(f"table 4,   {row:<8}" + "".join(fmt.format(cols[v][row]) for v in variants))
    summary.append((label, cols))
print("table 4 summary: survey | raw ATE rmse mm, drift %, inliers | auto | default")
for label, cols in summary:
    print(f"table 4 summary: {label:<44}" + " | ".join(
        f"{1000 * cols[v]['rmse']:6.1f} mm {cols[v]['drift %']:6.3f} % {cols[v]['inliers']:6.1f}" for v in variants))
PY
}
t4_runs=""
for seed in $seeds; do
  table4 "rough_$seed" "--seed $seed $rough"
  t4_runs+="degrade + color, seed $seed=rough_$seed|"
done
if [[ "${SEAMAP_BENCH_QUICK:-0}" != 1 ]]; then
  for seed in $t4_seeds; do
    table4 "t4_degrade_$seed" "--seed $seed --relief 0.15 --pitch-amp 3 --roll-amp 3 --degrade"
    table4 "t4_haze_$seed" "--seed $seed --relief 0.15 --pitch-amp 3 --roll-amp 3 --degrade --color --haze 0.8 --noise 4"
    t4_runs+="degrade (gray), seed $seed=t4_degrade_$seed|degrade + color + haze 0.8 + noise 4, seed $seed=t4_haze_$seed|"
  done
fi
IFS='|' read -r -a t4 <<<"${t4_runs%|}"
table4_print "${t4[@]}"
