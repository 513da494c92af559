#!/usr/bin/env bash
# Serving benchmark (called by bench.sh): the same tiles from nginx (a folder
# export) and from `seamap serve` (the MBTiles), loaded with wrk, 64
# connections asking for random existing tiles; then the same load on a
# mission a replay is writing; and one of 20 missions of a catalogue
# (`seamap serve FOLDER`). Prints requests/s, p50, p99, errors, ratio;
# then the peak memory under a 64 MiB chunked POST (bench_hostile_serve.sh).
#   bench_serve.sh SEAMAP_BIN MISSION.mbtiles SURVEY_DIR OUT_DIR
set -euo pipefail
seamap="$1" mission="$2" survey="$3"
out="$(mkdir -p "$4" && cd "$4" && pwd)"
duration="${SEAMAP_BENCH_SERVE_SECONDS:-8}"
folder="$out/tiles"
"$seamap" export "$mission" "$folder" --overwrite --quiet >/dev/null
(cd "$folder" && find . -regextype posix-extended -regex '\./[0-9]+/[0-9]+/[0-9]+\.(png|jpg|webp)' | sed 's|^\.||') >"$out/tiles.txt"

cat >"$out/tiles.lua" <<'LUA'
-- Random existing tiles; prints one machine-readable line at the end.
local paths = {}
for line in io.lines(os.getenv("TILE_LIST")) do paths[#paths + 1] = os.getenv("TILE_PREFIX") .. line end
math.randomseed(os.time() + tonumber(tostring({}):sub(8), 16) % 100000)
request = function() return wrk.format("GET", paths[math.random(#paths)]) end
done = function(summary, latency, requests)
  local e = summary.errors
  io.write(string.format("RESULT %.0f %.3f %.3f %d\n", summary.requests / (summary.duration / 1e6),
    latency:percentile(50) / 1000, latency:percentile(99) / 1000,
    e.connect + e.read + e.write + e.timeout + e.status))
end
LUA

pids=()
cleanup() { for p in "${pids[@]}"; do kill "$p" 2>/dev/null || true; done; wait 2>/dev/null || true; }
trap cleanup EXIT

wait_port() { for _ in $(seq 100); do curl -s -o /dev/null "http://127.0.0.1:$1/" && return 0; sleep 0.1; done; echo "port $1 never answered" >&2; return 1; }

# nginx serving the folder, as a static tile server would.
ngx="$out/nginx"; mkdir -p "$ngx/tmp"
user_line=""; [[ $(id -u) -eq 0 ]] && user_line="user root;"
cat >"$ngx/nginx.conf" <<NGINX
$user_line
worker_processes auto;
daemon off;
pid $ngx/nginx.pid;
error_log $ngx/error.log;
events { worker_connections 1024; }
http {
  access_log off;
  sendfile on; tcp_nopush on; tcp_nodelay on;
  keepalive_requests 100000;
  client_body_temp_path $ngx/tmp; proxy_temp_path $ngx/tmp; fastcgi_temp_path $ngx/tmp;
  uwsgi_temp_path $ngx/tmp; scgi_temp_path $ngx/tmp;
  types { image/png png; image/jpeg jpg; image/webp webp; }
  server { listen 127.0.0.1:18181; root $folder; etag on; }
}
NGINX
/usr/sbin/nginx -c "$ngx/nginx.conf" -p "$ngx" 2>"$ngx/stderr.log" &
pids+=($!)
"$seamap" serve "$mission" --host 127.0.0.1 --port 18182 --read-only >"$out/serve.log" 2>&1 &
pids+=($!)
wait_port 18181; wait_port 18182

load() {  # label, port, prefix -> "rps p50 p99 errors"
  TILE_LIST="$out/tiles.txt" TILE_PREFIX="$3" wrk -t2 -c64 -d"${duration}s" --latency -s "$out/tiles.lua" \
    "http://127.0.0.1:$2" 2>&1 | awk '/^RESULT/ {print $2, $3, $4, $5}'
}
report() {  # label, "rps p50 p99 errors"
  read -r rps p50 p99 err <<<"$2"
  printf '%-34s %9.0f req/s  p50 %6.2f ms  p99 %6.2f ms  errors %d\n' "$1" "$rps" "$p50" "$p99" "$err"
}
tiles=$(wc -l <"$out/tiles.txt")
# Alternate the two servers for a few rounds and keep each one's median run:
# a shared machine's noise then hits both alike.
rounds="${SEAMAP_BENCH_SERVE_ROUNDS:-5}"
: >"$out/nginx.runs"; : >"$out/seamap.runs"
for _ in $(seq "$rounds"); do
  load nginx 18181 "" >>"$out/nginx.runs"
  load seamap 18182 "/tiles" >>"$out/seamap.runs"
done
median() { sort -n "$1" | awk '{a[NR] = $0} END {print a[int((NR + 1) / 2)]}'; }
ngx_result=$(median "$out/nginx.runs")
sm_result=$(median "$out/seamap.runs")
report "nginx, folder of $tiles tiles" "$ngx_result"
report "seamap serve, MBTiles" "$sm_result"
python3 -c "import sys; a=float(sys.argv[1]); b=float(sys.argv[2]); print(f'seamap / nginx throughput          {b/a:9.2f}  (median of $rounds alternating ${duration} s runs each)')" \
  "${ngx_result%% *}" "${sm_result%% *}"

# The same load while a replay writes the mission being served.
live="$out/live.mbtiles"
echo '{"tile_format":"png","png_level":1}' >"$out/replay.json"
"$seamap" replay "$survey" --speed 8 --out "$live" --overwrite --host 127.0.0.1 --port 18183 --quiet \
  --exit-when-done --config "$out/replay.json" >"$out/replay.log" 2>&1 &
replay_pid=$!
pids+=($replay_pid)
wait_port 18183
live_result=$(load live 18183 "/tiles")
report "seamap replay (writing meanwhile)" "$live_result"
wait "$replay_pid" || { echo "replay failed: $(tail -3 "$out/replay.log")" >&2; exit 1; }

# A catalogue of 20 copies of the mission (`seamap serve FOLDER`): the load on one of them.
catalogue="$out/catalogue"
rm -rf "$catalogue" && mkdir -p "$catalogue"
for i in $(seq -w 1 20); do cp "$mission" "$catalogue/dive$i.mbtiles"; done
"$seamap" serve "$catalogue" --host 127.0.0.1 --port 18184 >"$out/catalogue.log" 2>&1 &
pids+=($!)
wait_port 18184
report "seamap serve FOLDER (20 missions)" "$(load catalogue 18184 /missions/dive07/tiles)"

# Peak memory under a hostile upload (64 MiB chunked POST, refused with 413).
"$(dirname "$0")/bench_hostile_serve.sh" "$seamap" "$mission" "$out" 18185
