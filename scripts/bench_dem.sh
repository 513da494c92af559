#!/usr/bin/env bash
# The height model from the photos (issue 29, deliverable 2) on the issue's
# survey shape: exact navigation, relief 0.3 m rms, 2 m altitude, lanes 0.9 m
# apart, 5 frames/s, JPEG; three seeds. Prints one line per figure: median
# and worst over the seeds, the issue's target beside it.
#
#   scripts/bench_dem.sh [BUILD_DIR]     (default build; builds seamap and dem_eval)
#   SEEDS="1 2 3" FRAMES=400 scripts/bench_dem.sh
set -euo pipefail
cd "$(dirname "$0")/.."
build=${1:-build}
out=out/bench/dem
seeds=${SEEDS:-"1 2 3"}
frames=${FRAMES:-400}
mkdir -p "$out"
cmake --build "$build" -j2 --target seamap dem_eval >/dev/null

results=()
for seed in $seeds; do
  survey=$out/survey_$seed
  if [ ! -f "$survey/truth/terrain.tif" ]; then
    rm -rf "$survey"
    "$build/seamap" simulate --out "$survey" --seed "$seed" --frames "$frames" --relief 0.3 \
      --altitude-min 2 --altitude-max 2 --line-spacing 0.9 --image-format jpg --quiet >/dev/null
  fi
  line=$("$build/dem_eval" "$survey" --quiet)
  echo "# seed $seed: $line" >&2
  results+=("$line")
done

# Median and worst of one field over the seeds ("max" or "min" is the worst).
figure() {
  local field=$1 worst=$2 values
  values=$(printf '%s\n' "${results[@]}" |
    awk -v f="$field" '{ for (i = 1; i < NF; ++i) if ($i == f) print $(i + 1) }' | sort -g)
  printf '%s\n' "$values" | awk -v w="$worst" '
    { v[++n] = $1 }
    END {
      m = (n % 2) ? v[(n + 1) / 2] : (v[n / 2] + v[n / 2 + 1]) / 2
      printf "%s %s", m, (w == "max" ? v[n] : v[1])
    }'
}
read -r rms_med rms_worst <<<"$(figure rms_mm max)"
read -r cov_med cov_worst <<<"$(figure coverage min)"
read -r w1_med w1_worst <<<"$(figure within1 min)"
read -r w2_med w2_worst <<<"$(figure within2 min)"
read -r cpu_med cpu_worst <<<"$(figure cpu_s max)"
read -r mb_med mb_worst <<<"$(figure peak_mb max)"
n=$(echo $seeds | wc -w)
echo "dem height rms vs truth (offset removed), $n seeds: median $rms_med mm, worst $rms_worst mm (target <= 20 mm)"
echo "dem coverage of the surveyed swath: median $cov_med, worst $cov_worst (target >= 0.90)"
echo "dem cells within 1 sigma: median $w1_med, worst $w1_worst (calibrated: 0.68)"
echo "dem cells within 2 sigma: median $w2_med, worst $w2_worst (calibrated: 0.95)"
echo "dem estimate CPU for $frames frames: median $cpu_med s, worst $cpu_worst s; peak memory median $mb_med MB, worst $mb_worst MB"
