#!/usr/bin/env bash
# Relief in the simulator (docs/TERRAIN.md): speed of `seamap simulate` on the issue's survey shape (lanes 0.9 m
# apart, 2 m altitude, 5 frames/s, 696x520 JPEG) on a flat seabed and with --relief 0.3, seeds 1-3. The marginal
# cost of a frame (CPU of 240 frames minus CPU of 120, per extra frame) is the renderer's; the whole run adds the
# texture, the relief and the writing. Alone: scripts/bench_relief.sh [build/seamap] [out/bench/relief]
set -euo pipefail
root="$(cd "$(dirname "$0")/.." && pwd)"
seamap="${1:-$root/build/seamap}" out="${2:-$root/out/bench/relief}"
if [[ ! -x "$seamap" ]]; then
  cmake -S "$root" -B "$root/build" -DCMAKE_BUILD_TYPE=Release >/dev/null && cmake --build "$root/build" -j2 --target seamap >/dev/null
fi
mkdir -p "$out"
shape=(--line-spacing 0.9 --altitude-min 2 --altitude-max 2 --image-format jpg --quiet --force)

# CPU seconds (user + sys) and wall seconds of one simulate run.
run() {
  local frames=$1 seed=$2 relief=$3
  /usr/bin/time -f "%U %S %e" -o "$out/time" "$seamap" simulate --out "$out/s_${relief}_${seed}_$frames" \
    --frames "$frames" --seed "$seed" --relief "$relief" "${shape[@]}" >/dev/null
  awk '{printf "%.3f %.3f\n", $1 + $2, $3}' "$out/time"
}

for relief in 0 0.3; do
  marginal=() per_frame=() fps=()
  for seed in 1 2 3; do
    read -r cpu_short _ < <(run 120 $seed $relief)
    read -r cpu_long wall_long < <(run 240 $seed $relief)
    marginal+=("$(awk -v a="$cpu_long" -v b="$cpu_short" 'BEGIN {printf "%.4f", (a - b) / 120}')")
    per_frame+=("$(awk -v a="$cpu_long" 'BEGIN {printf "%.4f", a / 240}')")
    fps+=("$(awk -v w="$wall_long" 'BEGIN {printf "%.2f", 240 / w}')")
    rm -rf "$out"/s_${relief}_${seed}_*
  done
  label=$([[ $relief == 0 ]] && echo "flat" || echo "--relief $relief")
  stats() { printf '%s\n' "$@" | sort -g | awk '{v[NR] = $1} END {printf "median %s worst %s", v[int((NR + 1) / 2)], v[NR]}'; }
  echo "relief: simulate $label, CPU s per extra frame (renderer, 696x520): $(stats "${marginal[@]}") (target < 0.1 with relief)"
  echo "relief: simulate $label, CPU s per frame, whole 240-frame run: $(stats "${per_frame[@]}")"
  echo "relief: simulate $label, frames/s wall on this machine, 240 frames: $(printf '%s\n' "${fps[@]}" | sort -g | awk '{v[NR] = $1} END {printf "median %s worst %s", v[int((NR + 1) / 2)], v[1]}')"
done
