#!/usr/bin/env bash
# Peak memory and time of issue 33's export cases (rows 12 and 14; row 4, the
# console's markup, is the browser test tests/e2e/hostile_text.e2e.mjs): each
# case runs `seamap export` under /usr/bin/time -v and prints one line: exit
# code, peak RSS, seconds and the first message. None may exceed 600 MB or 60 s.
#   bench_hostile_web.sh SEAMAP_BIN OUT_DIR
set -euo pipefail
seamap="$(cd "$(dirname "$1")" && pwd)/$(basename "$1")"
out="$(mkdir -p "$2" && cd "$2" && pwd)"
limit_mb=600
limit_s=60
base="$out/web_survey"
[[ -f "$base/nav.csv" ]] || "$seamap" simulate --out "$base" --frames 40 --line-length 4 --seed 5 --quiet --force >/dev/null

# The survey built with frame `$2` moved `$3` metres east (0: as simulated) into map `$1`.
build_map() {
  local map="$1" frame="$2" east_m="$3" nav="$out/web_nav.csv"
  awk -F, -v OFS=, -v line=$(($2 + 2)) -v east="$east_m" 'NR == line { $3 = $3 + east } { print }' \
    "$base/nav.csv" >"$nav"
  rm -rf "$map" "$map.lock"
  "$seamap" build --quiet --images "$base/photo" --nav "$nav" --camera "$base/camera.json" --origin 43.1,131.9 \
    --out "$map" >/dev/null 2>&1
}

# One line for a finished command: label, exit code, /usr/bin/time -v's file, the command's log.
report() {
  local label="$1" rc="$2" time_file="$3" log="$4" kb elapsed mb seconds over message
  kb="$(awk -F: '/Maximum resident set size/ {gsub(/ /, "", $2); print $2}' "$time_file")"
  elapsed="$(awk '/Elapsed \(wall clock\)/ {print $NF}' "$time_file")"
  seconds="$(awk -v t="${elapsed:-0}" 'BEGIN { n = split(t, p, ":"); s = 0; for (i = 1; i <= n; i++) s = s * 60 + p[i]; printf "%.1f", s }')"
  mb="$(awk -v kb="${kb:-0}" 'BEGIN { printf "%.1f", kb / 1024 }')"
  over="$(awk -v mb="$mb" -v s="$seconds" -v lm="$limit_mb" -v ls="$limit_s" 'BEGIN { if (mb > lm || s > ls) printf "OVER " }')"
  message="$(grep -m1 -E 'error|warning|stopped|exported|note' "$log" | sed 's/^ *//' | cut -c1-110 || true)"
  printf 'hostile %-38s  exit %d  peak RSS %6s MB  %5s s  %s(limit %d MB, %d s)  %s\n' "$label" "$rc" "$mb" "$seconds" \
    "$over" "$limit_mb" "$limit_s" "$message"
}

run_case() {  # label, then the export's arguments
  local label="$1" rc=0
  shift
  rm -rf "$out/export_out"*
  timeout 300 /usr/bin/time -v -o "$out/time.txt" "$seamap" export "$@" --quiet >"$out/log.txt" 2>&1 || rc=$?
  report "$label" "$rc" "$out/time.txt" "$out/log.txt"
}

echo "hostile web/export cases: $(nproc) cores, survey of $(($(wc -l <"$base/nav.csv") - 1)) frames of 696x520"
far="$out/web_far.mbtiles"
build_map "$far" 7 28000
run_case "GeoTIFF, a frame placed 28 km away" "$far" "$out/export_out.tif"
bounds="$(grep -o 'lie within [-0-9.,]*' "$out/log.txt" | cut -d' ' -f3)"
zoom="$(grep -o 'coarser --zoom (zoom [0-9]*' "$out/log.txt" | grep -o '[0-9]*$' || true)"
run_case "same, the --bounds it suggests" "$far" "$out/export_out.tif" --bounds "${bounds:-0,0,1,1}"
run_case "same, the --zoom it suggests (${zoom:-none})" "$far" "$out/export_out.tif" --zoom "${zoom:-0}"

# --allow-sparse: the user insists; Ctrl-C (SIGTERM) after 5 s must stop it and leave nothing.
rc=0
rm -f "$out/export_out.tif"*
/usr/bin/time -v -o "$out/time.txt" "$seamap" export "$far" "$out/export_out.tif" --allow-sparse --quiet \
  >"$out/log.txt" 2>&1 &
timer=$!
sleep 5
child="$(pgrep -P "$timer" || true)"  # the export: /usr/bin/time's child
[[ -n "$child" ]] && kill -TERM "$child"
wait "$timer" || rc=$?
left="$(find "$out" -maxdepth 1 -name 'export_out.tif*' | wc -l)"
report "same, --allow-sparse, SIGTERM at 5 s" "$rc" "$out/time.txt" "$out/log.txt"
[[ "$left" == 0 ]] || echo "hostile   ^ left $left file(s) behind"

# Row 14: a map another process is still building (a replay at the survey's pace), then interrupted.
live="$out/web_live.mbtiles"
rm -rf "$live" "$live.lock"
"$seamap" replay "$base" --speed 1 --out "$live" --port 0 --host 127.0.0.1 --exit-when-done --quiet \
  >"$out/replay.txt" 2>&1 &
replay=$!
for _ in $(seq 1 100); do
  # (sqlite3 would create the file if asked before the replay does)
  [[ -f "$live" && "$(sqlite3 -readonly "$live" "select value from metadata where name = 'seamap_state'" \
    2>/dev/null)" == building ]] && break
  sleep 0.1
done
run_case "a map still being built, to a folder" "$live" "$out/export_out"
run_case "the same with --partial" "$live" "$out/export_out" --partial
kill -KILL "$replay" 2>/dev/null || true
wait "$replay" 2>/dev/null || true
run_case "the same map, its builder killed" "$live" "$out/export_out.pmtiles"
rm -rf "$out/export_out"* "$out/time.txt" "$out/log.txt" "$out/replay.txt" "$out/web_nav.csv"
