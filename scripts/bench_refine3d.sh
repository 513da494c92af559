#!/usr/bin/env bash
# Refinement in 3-D (docs/TERRAIN.md, "Refinement in 3-D"): accuracy of
# `seamap trajectory --mode refine` (the bundle adjustment, and the planar
# pose graph beside it) on drifting surveys like the issue's, over a few
# seeds, and its cost at three survey lengths. Prints one line per figure.
#
#   SEAMAP_BIN=build/seamap            the binary
#   SEAMAP_BENCH_SEEDS="1 2 3"         seeds of the accuracy surveys
#   SEAMAP_BENCH_FRAMES=720            frames of an accuracy survey
#   SEAMAP_BENCH_CASES="rugged relief015 relief005 flat"   (the issue's target case first; "" to skip)
#   SEAMAP_BENCH_METHODS="auto bundle:1000 planar"   refine methods of the accuracy surveys
#                                      (bundle: as auto past 450 frames, in windows of 300; bundle:N: the
#                                      bundle in windows of N frames, --bundle-window N; N >= the frames:
#                                      one global bundle)
#   SEAMAP_BENCH_SCALING="800 3800 20000"   frames of the scaling surveys ("" to skip)
#   SEAMAP_BENCH_SCALING_SMALL=1       small frames (348x260) at every length (a loaded machine)
#   SEAMAP_BENCH_SCALING_METHODS="planar bundle"   refine methods of the scaling surveys
#   SEAMAP_BENCH_BUNDLE_WINDOW=300     --bundle-window of the scaling runs (frames a window, as `auto` past
#                                      450 frames)
set -euo pipefail
cd "$(dirname "$0")/.."
seamap=${SEAMAP_BIN:-$PWD/build/seamap}
seeds=${SEAMAP_BENCH_SEEDS:-"1 2 3"}
frames=${SEAMAP_BENCH_FRAMES:-720}
cases=${SEAMAP_BENCH_CASES-"rugged relief015 relief005 flat"}
methods=${SEAMAP_BENCH_METHODS:-"auto bundle:1000 planar"}
scaling=${SEAMAP_BENCH_SCALING-"800 3800 20000"}
small_only=${SEAMAP_BENCH_SCALING_SMALL:-0}
scaling_methods=${SEAMAP_BENCH_SCALING_METHODS:-"planar bundle"}
bundle_window=${SEAMAP_BENCH_BUNDLE_WINDOW:-300}
out=$PWD/out/bench/refine3d
mkdir -p "$out"
drift="--nav-drift 0.5 --nav-noise 0.005 --heading-noise 0.5"
survey="--image-format jpg --line-length 14 --line-spacing 0.9 $drift"

case_args() {
  case "$1" in
    flat) echo "" ;;
    relief005) echo "--relief 0.05" ;;
    relief015) echo "--relief 0.15" ;;
    rugged) echo "--relief 0.15 --pitch-amp 3 --roll-amp 3 --degrade --color" ;;
  esac
}

# refine SURVEY_DIR TAG METHOD [extra]: prints "cpu_s peak_mb p90_mm ate_mm"
refine() {
  local dir=$1 tag=$2 method=$3
  shift 3
  if [[ "$method" == *:* ]]; then  # bundle:N
    set -- --bundle-window "${method#*:}" "$@"
    method=${method%%:*}
  fi
  /usr/bin/time -f "%U %S %M" -o "$out/$tag.time" "$seamap" trajectory --mode refine --images "$dir/photo" \
    --nav "$dir/nav.csv" --camera "$dir/camera.json" --origin 43.1,131.9 --quiet $drift --refine-method "$method" \
    --out "$out/$tag.csv" --report "$out/$tag.json" "$@" >/dev/null 2>"$out/$tag.log"
  "$seamap" trajectory-eval "$out/$tag.csv" "$dir/nav_truth.csv" --origin 43.1,131.9 --json "$out/$tag.eval.json" \
    >/dev/null 2>&1
  python3 - "$out/$tag.time" "$out/$tag.eval.json" <<'PY'
import json, sys
u, s, m = open(sys.argv[1]).read().split()[-3:]
e = json.load(open(sys.argv[2]))
print(f"{float(u) + float(s):.1f} {int(m) / 1024:.0f} {e['cross_p90_mm']:.1f} {e['ate_m'] * 1000:.1f}")
PY
}

summary() {  # label, target, values "p90 ate cpu" one per line on stdin
  python3 -c '
import statistics, sys
label, target = sys.argv[1], sys.argv[2]
rows = [list(map(float, l.split())) for l in sys.stdin if l.strip()]
if not rows: sys.exit()
def f(k): v = [r[k] for r in rows]; return f"median {statistics.median(v):6.1f} worst {max(v):6.1f}"
print(f"{label:<40} p90 {f(0)} mm  ATE {f(1)} mm  CPU {f(2)} s  ({len(rows)} seeds; {target})")
' "$@"
}

for c in $cases; do
  for method in $methods; do
    rows=""
    for seed in $seeds; do
      dir="$out/survey_${c}_$seed"
      [[ -f "$dir/nav_truth.csv" ]] || "$seamap" simulate --out "$dir" --frames "$frames" --seed "$seed" --force --quiet \
        $survey $(case_args "$c") >/dev/null 2>&1
      read -r cpu mb p90 ate < <(refine "$dir" "${c}_${method/:/_w}_$seed" "$method")
      rows+="$p90 $ate $cpu"$'\n'
    done
    target="target p90 <= 10 mm, ATE <= 20 mm, <= 180 s"
    [[ "$c" == flat ]] && target="flat today (planar): p90 3.7-4.4 mm, ATE ~14 mm"
    printf "%s" "$rows" | summary "$c x$frames: refine $method" "$target"
  done
done

# Cost against the survey's length: the same lawnmower, longer. The longest
# uses small frames (348x260) so that it fits the disk; the 800-frame survey
# is run at both sizes so the two can be compared. The bundle past
# --bundle-window frames is solved in windows (docs/BUNDLE_WINDOWS.md):
# each line also says its CPU over the previous length's against the frames'.
declare -A prev_cpu prev_n
for n in $scaling; do
  for size in full small; do
    [[ ("$n" -ge 20000 || "$small_only" == 1) && "$size" == full ]] && continue
    [[ "$n" -gt 800 && "$n" -lt 20000 && "$size" == small && "$small_only" != 1 ]] && continue
    extra=""
    [[ "$size" == small ]] && extra="--width 348 --height 260 --pixel-pitch-um 25.8"
    dir="$out/scale_${n}_$size"
    [[ -f "$dir/nav_truth.csv" ]] || "$seamap" simulate --out "$dir" --frames "$n" --seed 7 --force --quiet $survey $extra \
      >/dev/null 2>&1
    for method in $scaling_methods; do
      read -r cpu mb p90 ate < <(refine "$dir" "scale_${n}_${size}_$method" "$method" --bundle-window "$bundle_window")
      growth=""
      key="${size}_$method"
      [[ -n "${prev_cpu[$key]:-}" ]] && growth=$(python3 -c "import sys; c, pc, n, pn = map(float, sys.argv[1:]); print(f'{n / pn:.2f}x frames, {c / pc:.2f}x CPU; ')" \
        "$cpu" "${prev_cpu[$key]}" "$n" "${prev_n[$key]}")
      prev_cpu[$key]=$cpu
      prev_n[$key]=$n
      printf "%-44s CPU %7.1f s  peak RSS %5.0f MB  p90 %5.1f mm  ATE %5.1f mm  (%starget: 4x frames <= 5x CPU; < 1500 MB at 20,000)\n" \
        "scaling x$n ($size frames): refine $method" "$cpu" "$mb" "$p90" "$ate" "$growth"
      # Where a windowed bundle's CPU goes: its windows' solves against the rest (features, pairs, tracks).
      if [[ "$method" == bundle ]]; then
        python3 - "$out/scale_${n}_${size}_$method.json" <<'PY'
import json, sys
b = json.load(open(sys.argv[1]))["bundle"]
if b.get("windows", 1) > 1:
    print(f"  {b['windows']} windows: solve CPU median {b['window_cpu_s_median']:.1f} s, max {b['window_cpu_s_max']:.1f} s; "
          f"largest window {b['window_solved_frames_max']} frames solved + {b['window_held_frames_max']} held; "
          f"{b['iterations']} iterations in all; {b.get('linear_solver', '')}")
PY
      fi
    done
  done
done
