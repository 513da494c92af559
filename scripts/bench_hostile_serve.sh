#!/usr/bin/env bash
# Peak memory of `seamap serve` under a hostile upload (issue 17): a 64 MiB
# chunked POST, which the server must refuse (413) once it passes the 64 KiB
# body limit, without reading it whole. Prints the answer's status and the
# server's peak RSS from /usr/bin/time -v (cap: far below 600 MB).
#   bench_hostile_serve.sh SEAMAP_BIN MISSION.mbtiles OUT_DIR [PORT]
set -euo pipefail
seamap="$1" mission="$2"
out="$(mkdir -p "$3" && cd "$3" && pwd)"
port="${4:-18185}"
/usr/bin/time -v -o "$out/hostile_serve.time" "$seamap" serve "$mission" --host 127.0.0.1 --port "$port" \
  --read-only >"$out/hostile_serve.log" 2>&1 &
timer=$!
sleep 0.2
server=$(ps -o pid= --ppid "$timer" | tr -d ' ')  # GNU time ignores SIGINT: stop seamap itself
trap 'kill -INT "$server" 2>/dev/null || true' EXIT
for _ in $(seq 100); do curl -s -o /dev/null "http://127.0.0.1:$port/api/status" && break; sleep 0.1; done
# 64 MiB sent by curl as a chunked body (no Content-Length).
status=$(head -c $((64 << 20)) /dev/zero | tr '\0' 'a' |
  curl -s -o "$out/hostile_answer.json" -w '%{http_code}' -X POST -H 'Transfer-Encoding: chunked' \
    -H 'Content-Type: application/json' --data-binary @- "http://127.0.0.1:$port/api/detections" || true)
kill -INT "$server"
wait "$timer" 2>/dev/null || true
trap - EXIT
peak_mb=$(awk -F': ' '/Maximum resident set size/ {printf "%.1f", $2 / 1024}' "$out/hostile_serve.time")
printf '%-36s %9s MB  (answer %s: %s; cap 600 MB)\n' "serve peak RSS, 64 MiB chunked POST" "$peak_mb" "$status" \
  "$(head -c 80 "$out/hostile_answer.json")"
