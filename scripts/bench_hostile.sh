#!/usr/bin/env bash
# Peak memory of the hostile-input cases (issue 17; called by bench.sh, or on
# its own): each case damages a copy of a small simulated survey the way
# tests/integration/hostile_input_test.cc does, builds it under
# /usr/bin/time -v, and prints one line: exit code, peak RSS, and the first
# message about the damage. None may exceed 600 MB.
#   bench_hostile.sh SEAMAP_BIN OUT_DIR
set -euo pipefail
seamap="$1"
out="$(mkdir -p "$2" && cd "$2" && pwd)"
limit_mb=600
base="$out/survey"
[[ -f "$base/nav.csv" ]] || "$seamap" simulate --out "$base" --frames 40 --line-length 4 --seed 5 --quiet --force >/dev/null

python_edit() {  # dir, python code run with d = the copy's folder
  python3 - "$1" "$2" <<'PY'
import json, math, os, struct, sys, zlib
d, code = sys.argv[1], sys.argv[2]
def nav_lines():
    return open(f"{d}/nav.csv").read().splitlines()
def write_nav(lines):
    open(f"{d}/nav.csv", "w").write("\n".join(lines) + "\n")
def set_field(line, field, value):
    lines = nav_lines(); parts = lines[line - 1].split(","); parts[field] = value
    lines[line - 1] = ",".join(parts); write_nav(lines)
def chunk(kind, data):
    return struct.pack(">I", len(data)) + kind + data + struct.pack(">I", zlib.crc32(kind + data))
def png(path, width, height, rows):  # 8-bit gray; `rows` zero rows deflated (a full flush per 100)
    z = zlib.compressobj(6); block = bytes((width + 1) * 100); idat = b""
    for _ in range(rows // 100): idat += z.compress(block) + z.flush(zlib.Z_FULL_FLUSH)
    idat += z.flush()
    ihdr = struct.pack(">IIBBBBB", width, height, 8, 0, 0, 0, 0)
    open(path, "wb").write(b"\x89PNG\r\n\x1a\n" + chunk(b"IHDR", ihdr) + chunk(b"IDAT", idat) + chunk(b"IEND", b""))
exec(code)
PY
}

run_case() {  # label, damage (python code or "fifo N"), extra build args, origin
  local label="$1" damage="$2" extra="$3" origin="${4:-43.1,131.9}" dir="$out/case" rc=0
  rm -rf "$dir" "$out/case.mbtiles"
  cp -r "$base" "$dir"
  if [[ "$damage" == fifo* ]]; then
    local f; f="$dir/photo/$(printf 'frame_%06d.png' "${damage#fifo }")"
    rm -f "$f" && mkfifo "$f"
  elif [[ -n "$damage" ]]; then
    python_edit "$dir" "$damage"
  fi
  if [[ "$origin" == antimeridian ]]; then  # the issue's origin; x_m moved so the lanes cross the meridian 53 m east
    origin="-16.5,179.9995"
    python_edit "$dir" "l = nav_lines(); mid = sum(float(x.split(',')[2]) for x in l[1:]) / (len(l) - 1)
shift = 0.0005 * 111319.49 * math.cos(math.radians(16.5)) - mid
write_nav([l[0]] + [','.join(p[:2] + [str(float(p[2]) + shift)] + p[3:]) for p in (x.split(',') for x in l[1:])])"
  fi
  # shellcheck disable=SC2086
  timeout 300 /usr/bin/time -v -o "$out/time.txt" "$seamap" build --quiet --images "$dir/photo" --nav "$dir/nav.csv" \
    --camera "$dir/camera.json" --origin "$origin" --out "$out/case.mbtiles" $extra >"$out/log.txt" 2>&1 || rc=$?
  local kb message
  kb="$(awk -F: '/Maximum resident set size/ {gsub(/ /, "", $2); print $2}' "$out/time.txt")"
  message="$(grep -m1 -E 'skipped:|error|warning: the survey' "$out/log.txt" | cut -c1-150 || true)"
  [[ -z "$message" ]] && message="$(grep -m1 'frames used' "$out/log.txt" | cut -c1-110 || true)"
  local mb over
  mb="$(awk -v kb="${kb:-0}" 'BEGIN { printf "%.1f", kb / 1024 }')"
  over="$(awk -v mb="$mb" -v limit="$limit_mb" 'BEGIN { if (mb > limit) printf "OVER " }')"
  printf 'hostile %-38s exit %d  peak RSS %6s MB %s(limit %d)  %s\n' "$label" "$rc" "$mb" "$over" "$limit_mb" "$message"
}

echo "hostile inputs: $(nproc) cores, survey of $(($(wc -l <"$base/nav.csv") - 1)) frames of 696x520"
run_case "none (the survey as simulated)" "" ""
run_case "nav x_m = 1e308" "set_field(3, 2, '1e308')" ""
run_case "nav altitude_m = 1e9" "set_field(4, 4, '1e9')" ""
run_case "nav altitude_m = 900 (survey at 2 m)" "set_field(5, 4, '900')" ""
run_case "survey across the antimeridian" "" "" antimeridian
run_case "PNG header claiming 100000x100000" "png(f'{d}/photo/frame_000003.png', 100000, 100000, 100)" ""
run_case "valid PNG of 30000x30000 zeros" "png(f'{d}/photo/frame_000005.png', 30000, 30000, 30000)" ""
run_case "CSV column name of 10 MB" "l = nav_lines(); l[0] += ',' + 'c' * (10 << 20); write_nav(l)" ""
run_case "CSV line of 10 MB" "l = nav_lines(); l[6] += '7' * (10 << 20); write_nav(l)" ""
run_case "--base-zoom 30" "" "--base-zoom 30"
run_case "FIFO among the images" "fifo 7" ""
run_case "camera fx = 1e999" "t = open(f'{d}/camera.json').read(); import re; open(f'{d}/camera.json', 'w').write(re.sub(r'\"fx\": *[0-9.e+-]+', '\"fx\": 1e999', t))" ""
run_case "one-colour first frame, gray survey" "w, h = 696, 520
raw = b''.join(b'\\x00' + bytes([200, 40, 20]) * w for _ in range(h))
ihdr = struct.pack('>IIBBBBB', w, h, 8, 2, 0, 0, 0)
open(f'{d}/photo/frame_000000.png', 'wb').write(b'\\x89PNG\\r\\n\\x1a\\n' + chunk(b'IHDR', ihdr) + chunk(b'IDAT', zlib.compress(raw)) + chunk(b'IEND', b''))" ""
rm -rf "$out/case" "$out/case.mbtiles"

# Issue 33's surfaces, one script per area (each prints the same kind of line, time beside memory).
here="$(dirname "$0")"
for area in model web server inputs; do
  "$here/bench_hostile_$area.sh" "$seamap" "$out/$area"
done
