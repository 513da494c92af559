#!/usr/bin/env bash
# Peak memory and time of issue 33's input cases (rows 9, 10, 11, 13, 14;
# called by bench_hostile.sh, or on its own): each case damages a copy of a
# small simulated survey (or writes a hostile file) the way
# tests/integration/hostile_inputs_test.cc does, runs seamap under
# /usr/bin/time -v, and prints one line: exit code, peak RSS, elapsed
# seconds, and the first line of the message about the damage. None may
# exceed 600 MB or 60 s (OVER says so).
#   bench_hostile_inputs.sh SEAMAP_BIN OUT_DIR
set -euo pipefail
seamap="$(cd "$(dirname "$1")" && pwd)/$(basename "$1")"
out="$(mkdir -p "$2" && cd "$2" && pwd)"
fixtures="$(cd "$(dirname "$0")/../tests/fixtures" && pwd)"
limit_mb=600
limit_s=60
base="$out/survey"
[[ -f "$base/nav.csv" ]] || "$seamap" simulate --out "$base" --frames 40 --line-length 4 --seed 5 --quiet --force >/dev/null
buoy="$out/buoy"
[[ -f "$buoy/buoy.csv" ]] || "$seamap" simulate-buoy --out "$buoy" --force --cloud-points 50 >/dev/null

py() {  # python code run with d = the case's folder
  python3 - "$out/case" "$1" <<'PY'
import glob, os, shutil, struct, sys, zlib
d, code = sys.argv[1], sys.argv[2]
def chunk(kind, data):
    return struct.pack(">I", len(data)) + kind + data + struct.pack(">I", zlib.crc32(kind + data))
def png(path, width, height, rows):  # 8-bit gray; `rows` zero rows deflated (a full flush per 100)
    z = zlib.compressobj(6); block = bytes((width + 1) * 100); idat = b""
    for _ in range(rows // 100): idat += z.compress(block) + z.flush(zlib.Z_FULL_FLUSH)
    idat += z.flush()
    ihdr = struct.pack(">IIBBBBB", width, height, 8, 0, 0, 0, 0)
    open(path, "wb").write(b"\x89PNG\r\n\x1a\n" + chunk(b"IHDR", ihdr) + chunk(b"IDAT", idat) + chunk(b"IEND", b""))
def black(path, width=696, height=520):
    raw = b"".join(b"\0" + bytes(width) for _ in range(height))
    ihdr = struct.pack(">IIBBBBB", width, height, 8, 0, 0, 0, 0)
    open(path, "wb").write(b"\x89PNG\r\n\x1a\n" + chunk(b"IHDR", ihdr) + chunk(b"IDAT", zlib.compress(raw)) + chunk(b"IEND", b""))
def frames():
    return sorted(glob.glob(f"{d}/photo/*.png"))
def shift_times(first_frame, seconds):
    lines = open(f"{d}/nav.csv").read().splitlines()
    for i in range(first_frame + 1, len(lines)):
        p = lines[i].split(","); p[1] = repr(float(p[1]) + seconds); lines[i] = ",".join(p)
    open(f"{d}/nav.csv", "w").write("\n".join(lines) + "\n")
exec(code)
PY
}

fresh() {  # a copy of the survey to damage
  rm -rf "$out/case" "$out/case.mbtiles" "$out/case.csv"
  cp -r "$base" "$out/case"
}

inputs() {
  echo "--quiet --images $out/case/photo --nav $out/case/nav.csv --camera $out/case/camera.json --origin 43.1,131.9"
}

run_case() {  # label, grep pattern for the message, command...
  local label="$1" pattern="$2" rc=0
  shift 2
  timeout 300 /usr/bin/time -v -o "$out/time.txt" "$@" >"$out/log.txt" 2>&1 || rc=$?
  local kb seconds message mb over
  kb="$(awk -F: '/Maximum resident set size/ {gsub(/ /, "", $2); print $2}' "$out/time.txt")"
  seconds="$(awk '/Elapsed \(wall clock\)/ {n = split($NF, t, ":"); s = 0; for (i = 1; i <= n; i++) s = s * 60 + t[i]; printf "%.1f", s}' "$out/time.txt")"
  message="$(grep -m1 -E "$pattern" "$out/log.txt" | cut -c1-110 || true)"
  [[ -z "$message" ]] && message="$(head -1 "$out/log.txt" | cut -c1-110)"
  mb="$(awk -v kb="${kb:-0}" 'BEGIN { printf "%.1f", kb / 1024 }')"
  over="$(awk -v mb="$mb" -v s="${seconds:-0}" -v lm="$limit_mb" -v ls="$limit_s" 'BEGIN { if (mb > lm || s > ls) printf "OVER " }')"
  printf 'hostile %-38s  exit %d  peak RSS %6s MB  %5s s  %s(limit %d MB, %d s)  %s\n' "$label" "$rc" "$mb" \
    "${seconds:-?}" "$over" "$limit_mb" "$limit_s" "$message"
}

echo "hostile inputs (issue 33): $(nproc) cores, survey of $(($(wc -l <"$base/nav.csv") - 1)) frames of 696x520"

# Row 9: the header check guards refine and visual odometry.
fresh
py "png(f'{d}/photo/frame_000003.png', 30000, 30000, 30000); png(f'{d}/photo/frame_000005.png', 30000, 30000, 30000)"
# shellcheck disable=SC2046
run_case "refine-nav, 2 PNGs of 30000x30000" "refine: frame_" \
  "$seamap" build --refine-nav $(inputs) --out "$out/case.mbtiles"
fresh
py "png(f'{d}/photo/frame_000004.png', 24000, 18000, 18000)"
# shellcheck disable=SC2046
run_case "trajectory vo, a PNG of 24000x18000" "image too large" \
  "$seamap" trajectory --mode vo $(inputs) --out "$out/case.csv"
stereo="$out/stereo"
if [[ ! -f "$stereo/object.json" ]]; then
  "$seamap" simulate-stereo --out "$stereo" --seed 1 --views 1 --supersample 1 >/dev/null
  "$seamap" stereo-model --calib "$stereo/stereo.yaml" --pairs "$stereo/overview" --out "$stereo/object.json" >/dev/null
fi
rm -rf "$out/case" && mkdir -p "$out/case/photo" && cp "$stereo"/approach/* "$out/case/photo/"
py "png(glob.glob(f'{d}/photo/*_left.png')[0], 24000, 18000, 18000)"
run_case "stereo-locate, a PNG of 24000x18000" "error" \
  "$seamap" stereo-locate --calib "$stereo/stereo.yaml" --model "$stereo/object.json" --pairs "$out/case/photo" \
  --out "$out/pose.json"

# Row 10: counts against the file's size; no /dev/zero.
printf 'ply\nformat binary_little_endian 1.0\nelement vertex 150000000\nproperty float x\nproperty float y\nproperty float z\nend_header\n' >"$out/big.ply"
georef=("$seamap" georef --buoy "$buoy/buoy.csv" --tether-length 30 --depth-csv "$buoy/depth.csv" --out "$out/georef.csv")
run_case "georef --points, PLY of 1.5e8 vertices" "error:" \
  "${georef[@]}" --keyframes "$buoy/keyframes.txt" --points "$out/big.ply" --points-out "$out/out.ply"
run_case "georef --keyframes /dev/zero" "error" "${georef[@]}" --keyframes /dev/zero
run_case "detect --classes /dev/zero" "error" \
  "$seamap" detect "$out/none.mbtiles" --model "$fixtures/yolo_v8_fixture.onnx" --classes /dev/zero

# Row 11: a jump in the navigation's time.
fresh
py "shift_times(20, 1e8)"
# shellcheck disable=SC2046
run_case "trajectory ekf, time jumps by 1e8 s" "jumps by" "$seamap" trajectory --mode ekf $(inputs) --out "$out/case.csv"
fresh
py "shift_times(20, 365.25 * 86400)"
# shellcheck disable=SC2046
run_case "trajectory vo, time jumps by a year" "jumps by" "$seamap" trajectory --mode vo $(inputs) --out "$out/case.csv"

# Row 13: a frozen camera, black photos.
fresh
py "f = frames(); [shutil.copy(f[0], x) for x in f[1:]]"
# shellcheck disable=SC2046
run_case "trajectory refine, a frozen camera" "poses corrected" \
  "$seamap" trajectory --mode refine $(inputs) --out "$out/case.csv"
# shellcheck disable=SC2046
run_case "refine-nav, a frozen camera" "poses corrected" \
  "$seamap" build --refine-nav $(inputs) --out "$out/case.mbtiles"
fresh
py "[black(x) for x in frames()]"
# shellcheck disable=SC2046
run_case "trajectory refine, black photos" "poses corrected" \
  "$seamap" trajectory --mode refine $(inputs) --out "$out/case.csv"
# shellcheck disable=SC2046
run_case "trajectory vo, black photos" "vo:" "$seamap" trajectory --mode vo $(inputs) --out "$out/case.csv"

# Row 14: values no survey holds.
mkdir -p "$out/truth"
echo '{"origin": {"lat": 43.1, "lon": 131.9}}' >"$out/truth/truth.json"
printf 'time_s,x_m,y_m,depth_m,heading_deg\n0,1,2,30,10\n' >"$out/truth/truth.csv"
printf 'time_s,lat,lon,depth_m,heading_deg,good\n0,43.1,131.9,1e308,10,1\n' >"$out/eval.csv"
run_case "georef-eval, depth_m 1e308" "error" "$seamap" georef-eval --nav "$out/eval.csv" --truth "$out/truth"
printf 'time_s,lat,lon,depth_m,heading_deg,good\n' >"$out/eval.csv"
run_case "georef-eval, a header and no keyframes" "error" "$seamap" georef-eval --nav "$out/eval.csv" --truth "$out/truth"
echo '{"world_from_camera": {"pair_000": [[1,0,0,1e300],[0,1,0,0],[0,0,1,0],[0,0,0,1]]}}' >"$out/motion.json"
run_case "stereo-locate --motion, 1e300 m" "error" \
  "$seamap" stereo-locate --calib "$out/none.yaml" --model "$out/none.json" --pairs "$out" --motion "$out/motion.json" \
  --out "$out/pose.json"
rm -rf "$out/case" "$out/case.mbtiles" "$out/case.csv"
