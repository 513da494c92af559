#!/usr/bin/env bash
# Peak memory and time of the server's hostile cases (issue 33, the server's
# rows; called by bench_hostile.sh, or on its own): each case damages copies
# of a small built mission the way tests/integration/hostile_server_test.cc
# does, serves them as a catalogue (`seamap serve FOLDER`) under
# /usr/bin/time -v, sends the requests of the case, stops the server with
# SIGTERM and prints one line: the server's exit code, its peak RSS and time,
# and the first answer about the damage. None may exceed 600 MB or 60 s.
#   bench_hostile_server.sh SEAMAP_BIN OUT_DIR
set -euo pipefail
seamap="$(cd "$(dirname "$1")" && pwd)/$(basename "$1")"
out="$(mkdir -p "$2" && cd "$2" && pwd)"
limit_mb=600
limit_s=60
base="$out/survey"
[[ -f "$base/nav.csv" ]] || "$seamap" simulate --out "$base" --frames 8 --line-length 2 --seed 7 --quiet --force >/dev/null
map="$out/base.mbtiles"
[[ -f "$map" ]] || "$seamap" build --quiet --images "$base/photo" --nav "$base/nav.csv" --camera "$base/camera.json" \
  --origin 43.1,131.9 --out "$map" >/dev/null

sql() { python3 -c 'import sqlite3, sys; c = sqlite3.connect(sys.argv[1]); c.executescript(sys.argv[2]); c.commit()' "$@"; }
get() { curl -s -m 30 "http://127.0.0.1:$port$1"; }
first_line() { head -c 2000 | head -n1 | cut -c1-110; }

# label, setup (shell code run in $dir with $maps the catalogue), requests (shell code: prints the message), ulimit -n
run_case() {
  local label="$1" setup="$2" requests="$3" files="${4:-1024}" dir="$out/case" rc=0
  rm -rf "$dir" 2>/dev/null || { sleep 1 && rm -rf "$dir"; }  # a stopped server's last SQLite files
  mkdir -p "$dir/maps"
  local maps="$dir/maps"
  (cd "$dir" && maps="$maps" map="$map" base="$base" eval "$setup")
  (ulimit -n "$files" && exec /usr/bin/time -v -o "$out/time.txt" "$seamap" serve "$maps" --host 127.0.0.1 --port 0) \
    >"$out/serve.out" 2>"$out/serve.err" &
  local pid=$!
  port=""
  for _ in $(seq 200); do
    port="$(sed -n 's|.*http://127.0.0.1:\([0-9]*\)/.*|\1|p' "$out/serve.out" | head -n1)"
    [[ -n "$port" ]] && break
    sleep 0.1
  done
  local message
  message="$(cd "$dir" && maps="$maps" eval "$requests" 2>&1 | first_line || true)"
  local server
  server="$(pgrep -P "$pid" | head -n1 || true)"  # seamap, the child of /usr/bin/time
  kill -TERM "${server:-$pid}" 2>/dev/null || true
  local waited=0
  while kill -0 "$pid" 2>/dev/null && ((waited < 150)); do sleep 0.1; waited=$((waited + 1)); done
  if kill -0 "$pid" 2>/dev/null; then
    kill -KILL "${server:-$pid}" 2>/dev/null || true
    message="SIGTERM did not stop the server; $message"
  fi
  wait "$pid" || rc=$?
  local kb elapsed mb seconds over
  kb="$(awk -F: '/Maximum resident set size/ {gsub(/ /, "", $2); print $2}' "$out/time.txt")"
  elapsed="$(awk '/Elapsed \(wall clock\)/ {print $NF}' "$out/time.txt")"
  mb="$(awk -v kb="${kb:-0}" 'BEGIN { printf "%.1f", kb / 1024 }')"
  seconds="$(awk -v t="${elapsed:-0}" 'BEGIN { n = split(t, p, ":"); s = 0; for (i = 1; i <= n; i++) s = s * 60 + p[i]; printf "%.1f", s }')"
  over="$(awk -v mb="$mb" -v s="$seconds" -v lm="$limit_mb" -v ls="$limit_s" 'BEGIN { if (mb > lm || s > ls) printf "OVER " }')"
  printf 'hostile %-38s  exit %d  peak RSS %6s MB  %5s s  %s(limit %d MB, %d s)  %s\n' "$label" "$rc" "$mb" "$seconds" \
    "$over" "$limit_mb" "$limit_s" "$message"
}

echo "hostile server: $(nproc) cores, missions of $(($(wc -l <"$base/nav.csv") - 1)) frames; server time includes ~3 s of requests"
run_case "none (one mission as built)" 'cp "$map" "$maps/dive.mbtiles"' \
  'get /missions/dive/api/status | head -c 110'
run_case "frame footprint [[null,1]] (row 1)" \
  'cp "$map" "$maps/good.mbtiles"; cp "$map" "$maps/bad.mbtiles"; sql "$maps/bad.mbtiles" "UPDATE frames SET footprint = '"'"'[[null,1]]'"'"' WHERE id = 2"' \
  'for i in 1 2 3; do get /missions/bad/api/status; echo; sleep 1.2; done | head -n1; get /missions/good/api/status >/dev/null || echo "good mission: no answer"'
run_case "detection box [[null,1]], lat NaN, inf" \
  'cp "$map" "$maps/dive.mbtiles"; sql "$maps/dive.mbtiles" "INSERT INTO detections (id, class, score, lat, lon, source, seq, box) VALUES (4, '"'"'fine'"'"', 0.5, 43.1, 131.9, '"'"'recogniser'"'"', 4, NULL), (1, '"'"'a'"'"', 0.5, 43.1, 131.9, '"'"'recogniser'"'"', 1, '"'"'[[null,1]]'"'"'), (2, '"'"'b'"'"', 0.5, NULL, 131.9, '"'"'recogniser'"'"', 2, NULL), (3, '"'"'c'"'"', 0.5, 9e999, 131.9, '"'"'recogniser'"'"', 3, NULL)"' \
  'echo "unreadable_detections $(get /missions/dive/api/status | python3 -c "import json, sys; print(json.load(sys.stdin).get(\"unreadable_detections\"))"), served $(get /missions/dive/api/detections | python3 -c "import json, sys; print(len(json.load(sys.stdin)[\"features\"]))")"'
run_case "232,362 detections, /api/detections" \
  'cp "$map" "$maps/dive.mbtiles"; sql "$maps/dive.mbtiles" "WITH RECURSIVE n(i) AS (SELECT 1 UNION ALL SELECT i + 1 FROM n WHERE i < 232362) INSERT INTO detections (id, class, score, lat, lon, source, seq, box, levels, frames, model, status) SELECT i, '"'"'rock'"'"', 0.001, 43.1 + i * 1e-9, 131.9, '"'"'recogniser'"'"', i, '"'"'[[131.9,43.1],[131.9,43.10001],[131.90001,43.10001],[131.90001,43.1],[131.9,43.1]]'"'"', '"'"'[24]'"'"', '"'"'[0]'"'"', '"'"'m.onnx#abc'"'"', '"'"'unconfirmed'"'"' FROM n"' \
  'for i in 1 2 3; do get /missions/dive/api/detections >/dev/null; done; get /missions/dive/api/detections | python3 -c "import json, sys; j = json.load(sys.stdin); print(len(j[\"features\"]), \"features, next:\", j.get(\"next\"))"'
run_case "since=1e19 / 1e300 (row 8)" \
  'cp "$map" "$maps/dive.mbtiles"; sql "$maps/dive.mbtiles" "INSERT INTO detections (id, class, score, lat, lon, source, seq) VALUES (1, '"'"'a'"'"', 0.5, 43.1, 131.9, '"'"'recogniser'"'"', 1)"' \
  'echo "$(get "/missions/dive/api/detections?since=1e19" | head -c 60) .bin?since=1e300: $(curl -s -D - -o /dev/null "http://127.0.0.1:$port/missions/dive/api/detections.bin?since=1e300" | grep -i x-seamap-records | tr -d "\r")"'
run_case "image_path out of the photo folder" \
  'cp -r "$base/photo" photo; mkdir private; cp photo/frame_000000.png private/secret.png; cp "$map" "$maps/dive.mbtiles"; sql "$maps/dive.mbtiles" "UPDATE frames SET image_path = '"'"'$PWD/photo/'"'"' || image; UPDATE frames SET image_path = '"'"'$PWD/private/secret.png'"'"' WHERE id = 0"' \
  'get /missions/dive/api/frames/0/image | head -c 300'
run_case "symlink out of the photo folder" \
  'cp -r "$base/photo" photo; mkdir private; cp photo/frame_000000.png private/secret.png; rm photo/frame_000002.png; ln -s "$PWD/private/secret.png" photo/frame_000002.png; cp "$map" "$maps/dive.mbtiles"; sql "$maps/dive.mbtiles" "UPDATE frames SET image_path = '"'"'$PWD/photo/'"'"' || image"' \
  'get /missions/dive/api/frames/2/image | head -c 300'
run_case "FIFO photo, 200 requests" \
  'cp -r "$base/photo" photo; rm photo/frame_000001.png; mkfifo photo/frame_000001.png; cp "$map" "$maps/dive.mbtiles"; sql "$maps/dive.mbtiles" "UPDATE frames SET image_path = '"'"'$PWD/photo/'"'"' || image"' \
  'for i in $(seq 200); do curl -s -m 30 -o /dev/null "http://127.0.0.1:$port/missions/dive/api/frames/1/image" & done; wait; get /missions/dive/api/frames/1/image; curl -s -m 5 -o /dev/null -w " /api/status %{http_code}" "http://127.0.0.1:$port/missions/dive/api/status"'
run_case "mission file mv-replaced while served" \
  'cp "$map" "$maps/dive.mbtiles"; cp "$map" next.mbtiles; sql next.mbtiles "INSERT INTO detections (id, class, score, lat, lon, source, seq) VALUES (1, '"'"'replaced'"'"', 0.5, 43.1, 131.9, '"'"'recogniser'"'"', 1)"' \
  'get /missions/dive/api/detections >/dev/null; mv next.mbtiles "$maps/dive.mbtiles"; sleep 1.5; get /missions/dive/api/detections | python3 -c "import json, sys; print(\"after mv:\", [f[\"properties\"][\"class\"] for f in json.load(sys.stdin)[\"features\"]])"'
run_case "120 missions, ulimit -n 512" \
  'for i in $(seq 120); do cp "$map" "$maps/d$i.mbtiles"; done' \
  'ok=0; for i in $(seq 120); do c="$(curl -s -m 30 -o /dev/null -w "%{http_code}" "http://127.0.0.1:$port/missions/d$i/api/status")"; [[ "$c" == 200 ]] && ok=$((ok + 1)); done; echo "$ok of 120 missions answered /api/status; $(grep -c "unable to open" "'"$out"'/serve.err" || true) open errors"' 512
rm -rf "$out/case" 2>/dev/null || { sleep 1 && rm -rf "$out/case"; }
