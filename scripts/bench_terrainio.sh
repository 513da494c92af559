#!/usr/bin/env bash
# The height model in the mission and to the user (issue 29, docs/TERRAIN.md):
# on simulated surveys built as usual, a synthetic height model over the
# frames' footprints (tests/tools/seed_terrain: 5 cm cells, a 0.4 m mound and
# ripples, a hole; what `build --terrain` will store) is kept in the mission
# with its relief layer; then the DEM export, read back by gdalinfo, and
# /api/terrain on a real `seamap serve`. One line per figure, median and
# worst over the seeds.
#   scripts/bench_terrainio.sh [SEEDS]      (default 3; SEAMAP_BUILD_DIR as scripts/test.sh)
set -euo pipefail
root="$(cd "$(dirname "$0")/.." && pwd)"
build="${SEAMAP_BUILD_DIR:-$root/build}"
out="$root/out/bench/terrainio"
seeds="${1:-3}"
mkdir -p "$out"
cmake --build "$build" --target seamap seed_terrain -j2 >/dev/null
seamap="$build/seamap" seeder="$build/seed_terrain"
rows="$out/rows.txt"
: >"$rows"

now() { date +%s.%N; }
for seed in $(seq 1 "$seeds"); do
  s="$out/survey_$seed" map="$out/map_$seed.mbtiles"
  rm -rf "$s" "$map" "$map-wal" "$map-shm" "$out/dem_$seed.tif"
  "$seamap" simulate --out "$s" --frames 200 --line-length 8 --seed "$seed" --quiet >/dev/null
  "$seamap" build --images "$s/photo" --nav "$s/nav.csv" --camera "$s/camera.json" --origin 43.1,131.9 \
    --out "$map" --quiet >/dev/null 2>&1
  # CPU seconds (user + system, the process's start included): wall time means little on a shared machine.
  /usr/bin/time -f "%U %S" -o "$out/cpu_store_$seed.txt" "$seeder" "$map" >"$out/probe_$seed.json"
  /usr/bin/time -f "%U %S" -o "$out/cpu_dem_$seed.txt" "$seamap" export "$map" "$out/dem_$seed.tif" --dem >/dev/null
  cpu_store=$(awk '{print $1 + $2}' "$out/cpu_store_$seed.txt") cpu_dem=$(awk '{print $1 + $2}' "$out/cpu_dem_$seed.txt")
  read -r rows_ cols_ < <(sqlite3 "$map" "SELECT header FROM terrain" | jq -r '"\(.rows) \(.cols)"')
  bytes=$(sqlite3 "$map" "SELECT length(cells) FROM terrain")
  relief_tiles=$(sqlite3 "$map" "SELECT count(*) FROM tiles_relief")
  overviews=$(gdalinfo -json "$out/dem_$seed.tif" | jq '.bands[0].overviews | length')
  nodata=$(gdalinfo -json "$out/dem_$seed.tif" | jq '.bands[0].noDataValue')

  # /api/terrain at the probe (the mound's top) and at 200 points across the model.
  log="$out/serve_$seed.log"
  "$seamap" serve "$map" --host 127.0.0.1 --port 0 --read-only >"$log" 2>&1 &
  pid=$!
  for _ in $(seq 100); do grep -q "serving http" "$log" && break; sleep 0.1; done
  base=$(grep -o "http://127.0.0.1:[0-9]*/" "$log" | head -1)
  read -r lat lon want < <(jq -r '.probe | "\(.lat) \(.lon) \(.height_m)"' "$out/probe_$seed.json")
  got=$(curl -s "${base}api/terrain?lat=$lat&lon=$lon" | jq '.height_m')
  # A 20 x 10 lattice of points 2.2 x 1.1 m around the probe, by one curl (its connection kept alive).
  awk -v lat="$lat" -v lon="$lon" -v base="$base" 'BEGIN { for (k = 0; k < 200; k++)
    printf "url = \"%sapi/terrain?lat=%.9f&lon=%.9f\"\noutput = /dev/null\n", base, lat + (k % 20 - 10) * 1e-6,
      lon + (int(k / 20) - 5) * 1.4e-6 }' >"$out/urls_$seed.txt"
  ta=$(now)
  answered=$(curl -s -K "$out/urls_$seed.txt" -w '%{http_code}\n' | grep -c '^200$' || true)
  tb=$(now)
  kill "$pid" && wait "$pid" 2>/dev/null || true
  python3 -c "
cells = $rows_ * $cols_
print($seed, cells, $bytes / cells, $cpu_store, $relief_tiles, $cpu_dem, $overviews, $nodata,
      abs($got - $want) * 1000, $answered, ($tb - $ta) / 200 * 1000)" >>"$rows"
done

python3 - "$rows" <<'EOF'
import statistics, sys
rows = [list(map(float, line.split())) for line in open(sys.argv[1])]
col = lambda i: [r[i] for r in rows]
def line(what, i, unit, fmt, target, worst=max):
    v = col(i)
    print(f"terrainio {what}: median {statistics.median(v):{fmt}} {unit}, worst {worst(v):{fmt}} {unit} ({target})")
print(f"terrainio surveys: {len(rows)} seeds, 200 frames each, height models of {statistics.median(col(1)):.0f} cells (5 cm)")
line("stored model size", 2, "bytes/cell", ".2f", "zlib float32 height + sigma; raw 8 bytes/cell")
line("store model + draw relief layer (seed_terrain)", 3, "CPU s", ".2f", "once per build, after the estimate")
line("relief tiles", 4, "tiles", ".0f", "map's min zoom to half a cell")
line("export --dem", 5, "CPU s", ".2f", "gdalinfo reads it")
line("DEM overviews", 6, "levels", ".0f", ">= 1, nodata-aware AVERAGE", worst=min)
print(f"terrainio DEM nodata: {sorted(set(col(7)))} (target -32767 in holes and outside)")
line("/api/terrain height at the probe vs the stored model", 8, "mm", ".3f", "target 0: bilinear of the stored cells")
line("/api/terrain answered over the model", 9, "of 200", ".0f", "200 where the model has data", worst=min)
line("/api/terrain request (curl, loopback)", 10, "ms", ".2f", "interactive: a click in the console")
EOF
