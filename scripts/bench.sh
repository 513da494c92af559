#!/usr/bin/env bash
# Speed and memory figures (never asserted by tests). Prints one line per figure.
#   scripts/bench.sh            gray seed-geometry survey, colour survey, 2,000-frame memory run,
#                               serving (nginx vs seamap serve vs a live replay, wrk)
#   SEAMAP_BENCH_QUICK=1 ...    smaller surveys, for a quick look
#   SEAMAP_BENCH_SERVE=0 ...    builds only
#   SEAMAP_BENCH_RUNS=5 ...     runs per build line (default 3; the median is shown)
#   SEAMAP_BENCH_TRAJECTORY=0   skip the trajectory figures (refine, vo, ekf on the drifting survey)
#   SEAMAP_BENCH_EXPORT=0       skip the export figures (PMTiles, GeoTIFF beside gdal_translate)
#   SEAMAP_BENCH_STEREO=0       skip the stereo object figures; SEAMAP_BENCH_STEREO_SCENES=N (default 20)
#   SEAMAP_BENCH_HOSTILE=0      skip the hostile inputs' peak memory (scripts/bench_hostile.sh, alone:
#                               scripts/bench_hostile.sh build/seamap out/bench/hostile)
#   SEAMAP_BENCH_GEOREF=0       skip the buoy-GPS georeferencing figures (scripts/bench_georef.sh)
#   SEAMAP_BENCH_CONSOLE=0      skip the console's traffic during a 4x replay (Chromium)
#   SEAMAP_BENCH_DETECT=0       skip the recogniser's figures (docs/DETECT.md)
#   SEAMAP_BENCH_TERRAIN=0      skip the rugged-seabed figures (docs/TERRAIN.md: relief simulator, height model,
#                               true orthophoto, 3-D refinement, VO on relief; each script also runs alone)
set -euo pipefail
root="$(cd "$(dirname "$0")/.." && pwd)"
build="${SEAMAP_BUILD_DIR:-$root/build}"
out="$root/out/bench"
SEAMAP_BENCH=1 "$root/scripts/setup.sh"  # also valgrind, nginx and wrk
"$root/scripts/build.sh" >/dev/null
seamap="$build/seamap"
mkdir -p "$out"

quick="${SEAMAP_BENCH_QUICK:-0}"
gray_frames=400; colour_frames=200; long_frames=2000
[[ "$quick" == 1 ]] && { gray_frames=100; colour_frames=40; long_frames=300; }

simulate() {  # name, frames, extra simulate args
  local dir="$out/$1"
  if [[ ! -f "$dir/nav.csv" ]] || [[ "$(($(wc -l <"$dir/nav.csv") - 1))" != "$2" ]]; then
    "$seamap" simulate --out "$dir" --frames "$2" --force ${3:-} >/dev/null 2>&1
  fi
}

steal_ticks() { awk '/^cpu /{print $9, $2+$3+$4+$5+$6+$7+$8+$9}' /proc/stat; }

# Each build runs $runs times (a shared VM's neighbours move single runs by
# 15-25 %); the line shows the median run, the range of all of them, and the
# share of the runs' CPU time the hypervisor stole.
runs="${SEAMAP_BENCH_RUNS:-3}"
build() {  # name, config json (inline), label
  local dir="$out/$1" cfg="$out/$1.config.json" reports=() before after
  echo "$2" >"$cfg"
  before="$(steal_ticks)"
  for ((i = 1; i <= runs; i++)); do
    "$seamap" build --quiet --images "$dir/photo" --nav "$dir/nav.csv" --camera "$dir/camera.json" \
      --origin 43.1,131.9 --config "$cfg" --out "$out/$1.mbtiles" --overwrite --report "$out/$1.report.$i.json" >/dev/null \
      2> >(grep -v '^seamap build: ' >&2)
    reports+=("$out/$1.report.$i.json")
  done
  after="$(steal_ticks)"
  python3 - "$3" "$before" "$after" "${reports[@]}" <<'PY'
import json, sys
label, before, after, paths = sys.argv[1], sys.argv[2].split(), sys.argv[3].split(), sys.argv[4:]
runs = sorted((json.load(open(p)) for p in paths), key=lambda r: r['ms_per_frame'])
r = runs[(len(runs) - 1) // 2]  # the median run (the lower one of an even count)
steal = (int(after[0]) - int(before[0])) / max(1, int(after[1]) - int(before[1]))
spread = f"{runs[0]['ms_per_frame']:.2f}-{runs[-1]['ms_per_frame']:.2f}" if len(runs) > 1 else "one run"
print(f"{label:<34} {r['ms_per_frame']:7.2f} ms/frame  {r['frames_per_s']:7.1f} frames/s  "
      f"(cpu {r['cpu_ms_per_frame']:5.2f} ms/frame)  "
      f"tiles {r['tiles']:6d} ({r['tile_writes']} writes)  bytes {r['tile_bytes']:>11,d}  "
      f"peak RSS {r['peak_rss_bytes'] / 2**20:6.1f} MiB  "
      f"[median of {len(runs)}: {spread}, steal {100 * steal:.0f} %]")
PY
}

echo "seamap bench on $(nproc) cores, $(date -u +%Y-%m-%dT%H:%MZ)"
simulate gray "$gray_frames" "--image-format jpg"
simulate colour "$colour_frames" "--color --width 1392 --height 1040 --pixel-pitch-um 6.45 --image-format jpg --texture-res 0.001"
build gray '{"tile_format":"png","png_level":1}' "gray 696x520 x$gray_frames, png fast"
build gray '{"tile_format":"png","png_level":6}' "gray 696x520 x$gray_frames, png zlib-6"
build colour '{"tile_format":"png","png_level":1}' "colour 1392x1040 x$colour_frames, png fast"
build colour '{"tile_format":"jpg"}' "colour 1392x1040 x$colour_frames, jpeg"
build gray '{"tile_format":"png","enhance":{"ops":[{"op":"flatfield"},{"op":"dehaze","gate":false},{"op":"clahe","clip_limit":3}]},"layers":"enhanced"}' "gray x$gray_frames + default enhance chain"
"$seamap" enhance-report "$out/gray/photo" --ops default --max-frames 20 --detector orb 2>/dev/null |
  awk '/->/ && $NF ~ /^[0-9.]+$/ {print "enhance default chain, 696x520 gray:  " $NF " ms/frame (chain alone)"}' | head -1
# Crash-safe builds (docs/RESUME.md): checkpoints off, default (every 10 s), at every batch.
for every in 0 10 1e-9; do
  build gray "{\"tile_format\":\"png\",\"png_level\":1,\"checkpoint_seconds\":$every}" "gray x$gray_frames, checkpoint_seconds $every"
  python3 -c 'import json,sys; r=[json.load(open(p)) for p in sys.argv[1:]]; print("  checkpoints %s, ms each %s" % ([x["checkpoints"] for x in r], [round(1000*x["checkpoint_seconds"]/max(1,x["checkpoints"]),1) for x in r]))' $(seq -f "$out/gray.report.%g.json" 1 "$runs")
done
echo "camera rate: 5 frames/s (200 ms/frame budget); seed paper: 173 ms/frame on an Atom Z8350"
simulate long "$long_frames" "--image-format jpg --line-length 40"
build long '{"tile_format":"png","png_level":1}' "gray x$long_frames (memory)"
# Trajectories (docs/TRAJECTORIES.md): the 14 x 7 m lawnmower (lanes 0.9 m,
# 720 frames, 76 m) whose navigation drifts 0.5 m/min; and the same survey
# with USBL-like fixes (0.3 m white noise, no drift) for the ekf.
trajectory_figures() {
  local dir="$out/drift" usbl="$out/usbl" frames=720 noise="--nav-noise 0.005 --nav-drift 0.5 --heading-noise 0.5"
  [[ "$quick" == 1 ]] && frames=240
  simulate drift "$frames" "--image-format jpg --line-length 14 --line-spacing 0.9 --nav-drift 0.5 --nav-noise 0.005 --heading-noise 0.5"
  simulate usbl "$frames" "--image-format jpg --line-length 14 --line-spacing 0.9 --nav-noise 0.3 --heading-noise 0.5"
  local common="--camera $dir/camera.json --origin 43.1,131.9 --quiet"
  eval_line() {  # label, estimate csv, truth csv, seconds, extra text
    "$seamap" trajectory-eval "$2" "$3" --origin 43.1,131.9 --json "$out/eval.json" >/dev/null 2>&1
    python3 - "$1" "$out/eval.json" "$4" "$5" <<'PY'
import json, sys
label, path, seconds, extra = sys.argv[1], sys.argv[2], float(sys.argv[3]), sys.argv[4]
e = json.load(open(path))
print(f"{label:<34} ATE {e['ate_m']*1000:7.1f} mm  max {e['max_error_m']*1000:7.1f} mm  drift {e['drift_percent']:5.3f} %  "
      f"cross-pass p50 {e['cross_median_mm']:6.1f} p90 {e['cross_p90_mm']:6.1f} mm  {seconds:6.1f} s  {extra}")
PY
  }
  eval_line "drift x$frames: navigation" "$dir/nav.csv" "$dir/nav_truth.csv" 0 "(as recorded)"
  local t0 t1 t2
  since() { python3 -c "print(f'{$2 - $1:.1f}')"; }
  t0=$(date +%s.%N)
  "$seamap" trajectory --mode refine --images "$dir/photo" --nav "$dir/nav.csv" $common $noise \
    --out "$out/refine.csv" --report "$out/refine.json" 2>/dev/null >/dev/null
  t1=$(date +%s.%N)
  "$seamap" build --images "$dir/photo" --nav "$out/refine.csv" $common --out "$out/refined.mbtiles" --overwrite >/dev/null 2>&1
  t2=$(date +%s.%N)
  eval_line "drift x$frames: refine" "$out/refine.csv" "$dir/nav_truth.csv" "$(since "$t0" "$t2")" \
    "(refine $(since "$t0" "$t1") s + painting $(since "$t1" "$t2") s; target <= 90 s, p90 <= 10 mm)"
  for mode in vo ekf; do
    t0=$(date +%s.%N)
    "$seamap" trajectory --mode $mode --images "$dir/photo" --nav "$dir/nav.csv" $common $noise --out "$out/$mode.csv" \
      --report "$out/$mode.json" 2>/dev/null >/dev/null
    t1=$(date +%s.%N)
    eval_line "drift x$frames: $mode" "$out/$mode.csv" "$dir/nav_truth.csv" "$(since "$t0" "$t1")" \
      "($(python3 -c "import json; r = json.load(open('$out/$mode.json')); print(f\"{r['frames_per_s']:.1f} frames/s, mean VO NIS {r['mean_vo_nis']:.2f}\")"); vo target: drift <= 0.5 %, >= 5 frames/s)"
  done
  eval_line "usbl x$frames: navigation" "$usbl/nav.csv" "$usbl/nav_truth.csv" 0 "(0.3 m white noise)"
  t0=$(date +%s.%N)
  "$seamap" trajectory --mode ekf --images "$usbl/photo" --nav "$usbl/nav.csv" --camera "$usbl/camera.json" \
    --origin 43.1,131.9 --quiet --nav-noise 0.3 --nav-drift 0 --heading-noise 0.5 --out "$out/usbl_ekf.csv" 2>/dev/null >/dev/null
  t1=$(date +%s.%N)
  eval_line "usbl x$frames: ekf" "$out/usbl_ekf.csv" "$usbl/nav_truth.csv" "$(since "$t0" "$t1")" "(VO + fixes)"
}
# Exports (docs/EXPORT.md): the gray map as PMTiles and as a GeoTIFF of its
# deepest level; then that level beside gdal_translate, same COG options, on
# a copy whose deepest tiles are relabelled zoom 22 (GDAL's MBTiles driver
# refuses deeper maps): the same tiles and pixels, placed near 0,0.
export_figures() {
  local m="$out/gray.mbtiles" m22="$out/gray_as_z22.mbtiles"
  local cog="-co COMPRESS=DEFLATE -co BLOCKSIZE=256 -co RESAMPLING=AVERAGE -co NUM_THREADS=ALL_CPUS"
  timed() {  # label, output, command...: wall and CPU time, peak RSS, output size
    local label="$1" file="$2" s user sys kb
    shift 2
    rm -f "$file"
    /usr/bin/time -f "%e %U %S %M" -o "$out/export.time" "$@" >/dev/null 2>&1
    read -r s user sys kb <"$out/export.time"
    printf "%-40s %6.2f s (cpu %5.2f s)  peak RSS %6.1f MiB  %s %d bytes\n" "$label" "$s" \
      "$(awk -v u="$user" -v s="$sys" 'BEGIN { print u + s }')" "$(awk -v kb="$kb" 'BEGIN { print kb / 1024 }')" \
      "$(basename "$file")" "$(stat -c %s "$file")"
  }
  printf "%-40s %d tiles, %d bytes; deepest level %s\n" "export: gray map (MBTiles)" \
    "$(sqlite3 "$m" 'select count(*) from tiles')" "$(stat -c %s "$m")" \
    "$(sqlite3 "$m" 'select zoom_level || ": " || count(*) || " tiles" from tiles group by zoom_level order by zoom_level desc limit 1')"
  timed "export: gray -> PMTiles" "$out/gray.pmtiles" "$seamap" export "$m" "$out/gray.pmtiles" --quiet --overwrite
  timed "export: gray -> COG, deepest zoom" "$out/gray.tif" "$seamap" export "$m" "$out/gray.tif" --quiet --overwrite
  cp "$m" "$m22"
  sqlite3 "$m22" "delete from tiles where zoom_level < (select max(zoom_level) from tiles);
    update tiles set zoom_level = 22, tile_column = tile_column - (select min(tile_column) from tiles),
      tile_row = tile_row - (select min(tile_row) from tiles);
    update metadata set value = '22' where name in ('minzoom', 'maxzoom');
    delete from metadata where name in ('bounds', 'center'); vacuum;"
  timed "export: deepest as z22 -> COG, seamap" "$out/gray_as_z22.tif" "$seamap" export "$m22" "$out/gray_as_z22.tif" --quiet --overwrite
  # shellcheck disable=SC2086
  timed "export: deepest as z22 -> COG, gdal_translate" "$out/gray_as_z22_gdal.tif" gdal_translate -q -of COG $cog "$m22" "$out/gray_as_z22_gdal.tif"
}
[[ "${SEAMAP_BENCH_EXPORT:-1}" == 1 ]] && export_figures
[[ "${SEAMAP_BENCH_TRAJECTORY:-1}" == 1 ]] && trajectory_figures
# Stereo object reference (docs/STEREO.md): check-point error with 1, 2, 3 pairs and ICP, clear and
# degraded water, and few points (plain paint, haze, the object half out of view); the paper's figures beside.
if [[ "${SEAMAP_BENCH_STEREO:-1}" == 1 ]]; then
  stereo_scenes="${SEAMAP_BENCH_STEREO_SCENES:-20}"; [[ "$quick" == 1 ]] && stereo_scenes=3
  python3 "$root/scripts/bench_stereo.py" "$seamap" "$out" "$stereo_scenes" clear,degraded,few
fi
# Live refinement (replay --refine-nav) against build --refine-nav, with the worker's lag (docs/REFINE_LIVE.md).
[[ "${SEAMAP_BENCH_TRAJECTORY:-1}" == 1 ]] && SEAMAP_BIN="$seamap" SEAMAP_BENCH_PACED="$([[ "$quick" == 1 ]] && echo 0 || echo 1)" \
  SEAMAP_BENCH_FRAMES="$([[ "$quick" == 1 ]] && echo 240 || echo 720)" "$root/scripts/bench_refine_live.sh"
[[ "${SEAMAP_BENCH_HOSTILE:-1}" == 1 ]] && "$root/scripts/bench_hostile.sh" "$seamap" "$out/hostile"
[[ "${SEAMAP_BENCH_GEOREF:-1}" == 1 ]] && "$root/scripts/bench_georef.sh" "$seamap" "$out/georef" "$([[ "$quick" == 1 ]] && echo 5 || echo 20)"
[[ "${SEAMAP_BENCH_DETECT:-1}" == 1 ]] && "$root/scripts/bench_detect.sh" "$seamap" "$out/detect"
if [[ "${SEAMAP_BENCH_TERRAIN:-1}" == 1 ]]; then
  terrain_seeds=3; [[ "$quick" == 1 ]] && terrain_seeds=1
  "$root/scripts/bench_relief.sh" "$seamap" "$out/relief"
  SEEDS="$(seq -s ' ' 1 "$terrain_seeds")" SEAMAP_BUILD_DIR="$build" "$root/scripts/bench_dem.sh" "$build"
  "$root/scripts/bench_ortho.sh" "$seamap" "$out/ortho" "$terrain_seeds"
  SEAMAP_BUILD_DIR="$build" "$root/scripts/bench_terrainio.sh" "$terrain_seeds"
  SEAMAP_BIN="$seamap" SEAMAP_BENCH_SEEDS="$(seq -s ' ' 1 "$terrain_seeds")" "$root/scripts/bench_refine3d.sh"
  SEAMAP_BIN="$seamap" "$root/scripts/bench_vo.sh"
fi
if [[ "${SEAMAP_BENCH_SERVE:-1}" == 1 ]]; then
  "$root/scripts/bench_serve.sh" "$seamap" "$out/gray.mbtiles" "$out/gray" "$out/serve"
fi
# The console's traffic on a weak link: bytes Chromium receives during a 4x replay (issue 21 budget 0.3 Mbit/s).
if [[ "${SEAMAP_BENCH_CONSOLE:-1}" == 1 && -x /usr/bin/chromium && -d "$root/node_modules/playwright-core" ]]; then
  for low in 0 1; do
    SEAMAP_BIN="$seamap" SEAMAP_BW_REPORT=1 SEAMAP_BW_LOW=$low node "$root/tests/e2e/bandwidth.e2e.mjs" 2>/dev/null |
      sed -n 's/^# console traffic/console traffic/p'
  done
fi
