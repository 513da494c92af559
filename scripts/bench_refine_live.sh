#!/usr/bin/env bash
# Live refinement (replay --refine-nav, docs/REFINE_LIVE.md) on the bench's
# drifting survey (720 frames, lanes 0.9 m, navigation drifting 0.5 m/min):
# CPU time, peak memory and the final trajectory's cross-pass p90 against
# `build --refine-nav` on the same survey, at full speed and (optionally) at
# the camera's pace, with the worker's lag. One line per run.
#
#   SEAMAP_BIN=build/seamap          the binary
#   SEAMAP_BENCH_FRAMES=720          frames of the survey
#   SEAMAP_BENCH_LINE=14             lane length, metres (a short survey needs short lanes to cross itself)
#   SEAMAP_BENCH_PACED=1             also replay at --speed 1 (as long as the dive: 144 s for 720 frames)
#   SEAMAP_BENCH_MEMORY_MB=0         > 0: also the worker's features bounded to this many MB against no bound
#                                    (--refine-features-mb), both at SEAMAP_BENCH_MEMORY_SPEED (default 1)
set -euo pipefail
cd "$(dirname "$0")/.."
seamap=${SEAMAP_BIN:-$PWD/build/seamap}
frames=${SEAMAP_BENCH_FRAMES:-720}
line=${SEAMAP_BENCH_LINE:-14}
paced=${SEAMAP_BENCH_PACED:-1}
memory_mb=${SEAMAP_BENCH_MEMORY_MB:-0}
memory_speed=${SEAMAP_BENCH_MEMORY_SPEED:-1}
out=$PWD/out/bench/refine_live
mkdir -p "$out"
noise="--nav-noise 0.005 --nav-drift 0.5 --heading-noise 0.5"
survey="$out/drift${frames}x$line"
if [[ ! -f "$survey/nav.csv" ]]; then
  "$seamap" simulate --out "$survey" --frames "$frames" --force --image-format jpg --line-length "$line" \
    --line-spacing 0.9 $noise --quiet >/dev/null
fi

# run TAG COMMAND...: CPU seconds (user + sys) and peak RSS (MiB) of the command into $out/TAG.time
run() {
  local tag=$1
  shift
  /usr/bin/time -f "%U %S %M" -o "$out/$tag.time" "$@" >"$out/$tag.out" 2>"$out/$tag.err"
}
p90() {
  "$seamap" trajectory-eval "$1" "$survey/nav_truth.csv" --origin 43.1,131.9 --json "$out/eval.json" >/dev/null 2>&1
  python3 -c "import json; v = json.load(open('$out/eval.json'))['cross_p90_mm']; print('n/a' if v is None else f'{v:.1f}')"
}
cpu() { awk '{printf "%.1f", $1 + $2}' "$out/$1.time"; }
rss() { awk '{printf "%.0f", $3 / 1024}' "$out/$1.time"; }

run build "$seamap" build --images "$survey/photo" --nav "$survey/nav.csv" --camera "$survey/camera.json" \
  --origin 43.1,131.9 $noise --refine-nav --quiet --out "$out/build.mbtiles" --overwrite --trajectory-out "$out/build.csv"
build_p90=$(p90 "$out/build.csv")
echo "refine live x$frames: build --refine-nav           cpu $(cpu build) s  peak RSS $(rss build) MiB  cross-pass p90 $build_p90 mm"
speeds="max"
[[ "$paced" == 1 ]] && speeds="max 1"
for speed in $speeds; do
  rm -rf "$out/replay$speed.mbtiles"*
  run "replay$speed" "$seamap" replay "$survey" $noise --refine-nav --speed "$speed" --out "$out/replay$speed.mbtiles" \
    --trajectory-out "$out/replay$speed.csv" --host 127.0.0.1 --port 0 --quiet --exit-when-done
  ratio=$(python3 -c "print(f'{$(cpu "replay$speed") / max(0.1, $(cpu build)):.2f}')")
  echo "refine live x$frames: replay --refine-nav --speed $speed  cpu $(cpu "replay$speed") s (${ratio}x build's)  peak RSS $(rss "replay$speed") MiB  cross-pass p90 $(p90 "$out/replay$speed.csv") mm (target <= 10)"
  echo "  $(grep -m1 '^refine live:' "$out/replay$speed.out")"
  grep '^refine live: solve' "$out/replay$speed.err" | sed 's/^/  /' | tail -3 || true
done

# The worker's memory: every frame's features kept (no bound) against the bound.
if [[ "$memory_mb" != 0 ]]; then
  for mb in 0 "$memory_mb"; do
    tag="memory$mb"
    rm -rf "$out/$tag.mbtiles"*
    run "$tag" "$seamap" replay "$survey" $noise --refine-nav --refine-features-mb "$mb" --speed "$memory_speed" \
      --out "$out/$tag.mbtiles" --trajectory-out "$out/$tag.csv" --host 127.0.0.1 --port 0 --quiet --exit-when-done
    echo "refine live x$frames: --refine-features-mb $mb --speed $memory_speed  cpu $(cpu "$tag") s  peak RSS $(rss "$tag") MiB  cross-pass p90 $(p90 "$out/$tag.csv") mm"
    echo "  $(grep -m1 '^refine live:' "$out/$tag.out")"
  done
fi
