#!/usr/bin/env bash
# Peak memory and time of the hostile-model cases (issue 33 rows 2, 3, 5, 10,
# 14; called by bench_hostile.sh, or on its own): the shipped model damaged
# the way the issue did (an initializer declaring 1e8 elements, 20
# initializers removed), hand-built models (inf/NaN boxes, 51,200 boxes a
# window, hostile metadata), hostile options and classes files, and a map
# holding a record with NaN numbers, each run under /usr/bin/time -v on a
# small simulated survey. One line per case: exit code, peak RSS, seconds and
# the first line that says what happened. None may exceed 600 MB or 60 s.
#   bench_hostile_model.sh SEAMAP_BIN OUT_DIR
set -euo pipefail
seamap="$(cd "$(dirname "$1")" && pwd)/$(basename "$1")"
out="$(mkdir -p "$2" && cd "$2" && pwd)"
here="$(cd "$(dirname "$0")" && pwd)"
shipped="$here/../data/models/seabed_objects.onnx"
limit_mb=600
limit_s=60
survey="$out/survey"
map="$out/map.mbtiles"
[[ -f "$survey/nav.csv" ]] || "$seamap" simulate --out "$survey" --frames 40 --line-length 3 --seed 3 --quiet --force >/dev/null
origin=43.1,131.9  # as tests/integration/survey_fixture.h
[[ -f "$map" ]] || "$seamap" build --quiet --images "$survey/photo" --nav "$survey/nav.csv" --camera "$survey/camera.json" \
  --origin "$origin" --out "$map" >/dev/null

# The models: protobuf written and edited by hand (no onnx package needed).
python3 - "$out" "$shipped" <<'PY'
import struct, sys
out, shipped = sys.argv[1], sys.argv[2]
def varint(v):
    v &= (1 << 64) - 1; b = b""
    while v >= 0x80: b += bytes([(v & 0x7F) | 0x80]); v >>= 7
    return b + bytes([v])
def field(n, t, payload): return varint(n << 3 | t) + payload
def vfield(n, v): return field(n, 0, varint(v))
def bfield(n, b): return field(n, 2, varint(len(b)) + b)
def fields(buf):  # [(number, type, value or payload)]
    i, res = 0, []
    while i < len(buf):
        key, i = read_varint(buf, i); n, t = key >> 3, key & 7
        if t == 0: v, i = read_varint(buf, i)
        elif t == 1: v, i = buf[i:i + 8], i + 8
        elif t == 5: v, i = buf[i:i + 4], i + 4
        elif t == 2: ln, i = read_varint(buf, i); v, i = buf[i:i + ln], i + ln
        else: raise ValueError("group")
        res.append((n, t, v))
    return res
def read_varint(buf, i):
    v = s = 0
    while True:
        b = buf[i]; i += 1; v |= (b & 0x7F) << s; s += 7
        if b < 0x80: return v, i
def join(fs): return b"".join(vfield(n, v) if t == 0 else bfield(n, v) if t == 2 else field(n, t, v) for n, t, v in fs)
def edit_graph(model, fn):
    return join([(n, t, join(fn(fields(v))) if n == 7 else v) for n, t, v in fields(model)])
base = open(shipped, "rb").read()
# The largest initializer declares 1e8 elements, its data unchanged.
def big(graph):
    inits = [k for k, (n, t, v) in enumerate(graph) if n == 5]
    k = max(inits, key=lambda k: len(graph[k][2]))
    t = [(n, ty, v) for n, ty, v in fields(graph[k][2]) if n != 1]
    graph[k] = (5, 2, join([(1, 0, 100000000)] + t)); return graph
open(f"{out}/big_initializer.onnx", "wb").write(edit_graph(base, big))
def removed(graph):
    inits = [k for k, (n, t, v) in enumerate(graph) if n == 5][:20]
    return [g for k, g in enumerate(graph) if k not in inits]
open(f"{out}/no_initializers.onnx", "wb").write(edit_graph(base, removed))
# Planted models (tests/testing/onnx_builder.h): pool, 1x1 conv with zero weights whose bias is the output, reshape.
def tensor(name, dims, dtype, raw): return b"".join(vfield(1, d) for d in dims) + vfield(2, dtype) + bfield(8, name) + bfield(9, raw)
def value_info(name, dims):
    shape = b"".join(bfield(1, vfield(1, d)) for d in dims)
    return bfield(1, name) + bfield(2, bfield(1, vfield(1, 1) + bfield(2, shape)))
def planted(path, out_shape, values, meta):
    m = len(values)
    node = lambda op, i, o, a=b"": b"".join(bfield(1, x) for x in i) + b"".join(bfield(2, x) for x in o) + bfield(4, op) + a
    kernel = bfield(5, bfield(1, b"kernel_shape") + vfield(8, 1) + vfield(8, 1) + vfield(20, 7))
    graph = (bfield(1, node(b"GlobalAveragePool", [b"images"], [b"pooled"])) +
             bfield(1, node(b"Conv", [b"pooled", b"w", b"b"], [b"planted"], kernel)) +
             bfield(1, node(b"Reshape", [b"planted", b"shape"], [b"output0"])) + bfield(2, b"bench") +
             bfield(5, tensor(b"w", [m, 3, 1, 1], 1, bytes(12 * m))) +
             bfield(5, tensor(b"b", [m], 1, struct.pack(f"<{m}f", *values))) +
             bfield(5, tensor(b"shape", [len(out_shape)], 7, struct.pack(f"<{len(out_shape)}q", *out_shape))) +
             bfield(11, value_info(b"images", [1, 3, 64, 64])) + bfield(12, value_info(b"output0", out_shape)))
    model = vfield(1, 7) + bfield(7, graph) + bfield(8, vfield(2, 12))
    for k, v in meta.items(): model += bfield(14, bfield(1, k.encode()) + bfield(2, v.encode()))
    open(f"{out}/{path}", "wb").write(model)
def v8(rows): return [rows[i][j] for j in range(len(rows[0])) for i in range(len(rows))]
names = {"names": '["tyre", "crate"]'}
two = v8([(20, 24, 10, 8, 0.1, 0.8), (44, 40, 12, 12, 0.9, 0.2)])
inf, nan = float("inf"), float("nan")
planted("nan_boxes.onnx", [1, 6, 5], v8([(20, 24, 10, 8, 0.1, 0.8), (44, 40, 12, 12, 0.9, 0.2), (inf, 24, 10, 8, 0.9, 0.1),
                                         (30, nan, 10, 8, 0.1, 0.9), (30, 30, 10, 8, nan, 0.9)]), names)
n = 51200  # the issue's count: a 320 x 160 grid of 0.1 px boxes
planted("everything.onnx", [1, 6, n], v8([(0.1 + (i % 320) * 0.2, 0.1 + (i // 320) * 0.4, 0.1, 0.1, 0.01 + 0.9 * (i % 97) / 97, 0.005)
                                           for i in range(n)]), names)
planted("tiny_score.onnx", [1, 6, 2], two, dict(names, **{"seamap.min_score": "1e-300"}))
planted("long_score.onnx", [1, 6, 2], two, dict(names, **{"seamap.min_score": "7" * (10 << 20)}))
planted("huge_id.onnx", [1, 6, 2], two, {"names": "{0: 'tyre', 99999999999999: 'crate'}"})
planted("empty_names.onnx", [1, 6, 2], two, {"names": '["", ""]'})
PY

run_case() {  # label, command (arguments of seamap, run in OUT_DIR), [prepare: shell code run first], [line to show]
  local label="$1" args="$2" rc=0
  [[ -n "${3:-}" ]] && eval "$3"
  # shellcheck disable=SC2086
  (cd "$out" && timeout 300 /usr/bin/time -v -o "$out/time.txt" "$seamap" $args >"$out/log.txt" 2>&1) || rc=$?
  local kb elapsed message
  kb="$(awk -F: '/Maximum resident set size/ {gsub(/ /, "", $2); print $2}' "$out/time.txt")"
  elapsed="$(awk '/Elapsed \(wall clock\)/ {n = split($NF, p, ":"); s = 0; for (i = 1; i <= n; ++i) s = s * 60 + p[i]; print s}' "$out/time.txt")"
  message="$(grep -m1 -E "${4:-error|failed|warning|Segmentation|objects}" "$out/log.txt" | cut -c1-110 || true)"
  [[ -z "$message" ]] && message="$(head -1 "$out/log.txt" | cut -c1-110)"
  local mb over
  mb="$(awk -v kb="${kb:-0}" 'BEGIN { printf "%.1f", kb / 1024 }')"
  over="$(awk -v mb="$mb" -v s="${elapsed:-0}" -v lm="$limit_mb" -v ls="$limit_s" 'BEGIN { if (mb > lm || s > ls) printf "OVER " }')"
  printf 'hostile %-38s exit %d  peak RSS %6s MB  %5.1f s  %s(limit %d MB, %d s)  %s\n' "$label" "$rc" "$mb" \
    "${elapsed:-0}" "$over" "$limit_mb" "$limit_s" "$message"
}

cd "$out"
# shellcheck disable=SC2016  # expanded when run_case evals it
fresh='rm -rf "case.mbtiles" "case_copy.mbtiles"; cp "$map" "case.mbtiles"'
build="build --quiet --images survey/photo --nav survey/nav.csv --camera survey/camera.json --origin $origin --out built.mbtiles"
echo "hostile models: $(nproc) cores, survey of $(($(wc -l <"survey/nav.csv") - 1)) frames"
run_case "none (the shipped model)" "detect --quiet case.mbtiles" "$fresh" "[0-9]+ objects"
run_case "initializer of 1e8 elements (detect)" "detect --quiet case.mbtiles --model big_initializer.onnx" "$fresh"
run_case "initializer of 1e8 elements (build)" "$build --detect --detect-model big_initializer.onnx" \
  'rm -rf "built.mbtiles"'
run_case "20 initializers removed (detect)" "detect --quiet case.mbtiles --model no_initializers.onnx" "$fresh"
run_case "20 initializers removed (replay)" "replay survey --out replayed.mbtiles --speed max --port 0 --quiet --exit-when-done --detect --detect-model no_initializers.onnx" \
  'rm -rf "replayed.mbtiles"'
run_case "inf/NaN boxes" "detect --quiet case.mbtiles --model nan_boxes.onnx" "$fresh" "inf/NaN"
run_case "stored NaN record: detections-pack" "detections-pack case.mbtiles --out pack.bin" \
  "$fresh"'; python3 -c "import sqlite3; c = sqlite3.connect(\"case.mbtiles\"); c.execute(\"INSERT INTO detections (id, class, score, lat, lon, source, box) VALUES (999, \x27tyre\x27, 0.9, NULL, NULL, \x27recogniser\x27, \x27[[null,null],[null,null]]\x27)\"); c.commit()"'
run_case "stored NaN record: export" "export --quiet case.mbtiles case_copy.mbtiles"
run_case "51,200 boxes a window, min score 0.001" "detect --quiet case.mbtiles --model everything.onnx --min-score 0.001" "$fresh" "[0-9]+ objects"
run_case "--min-score 0" "detect --quiet case.mbtiles --model everything.onnx --min-score 0" "$fresh"
run_case "seamap.min_score 1e-300" "detect --quiet case.mbtiles --model tiny_score.onnx" "$fresh"
run_case "seamap.min_score of 10 MB" "detect --quiet case.mbtiles --model long_score.onnx" "$fresh"
run_case "--classes /dev/zero" "detect --quiet case.mbtiles --classes /dev/zero" "$fresh"
run_case "names with id 99999999999999" "detect --quiet case.mbtiles --model huge_id.onnx" "$fresh"
run_case "all-empty class names" "detect --quiet case.mbtiles --model empty_names.onnx" "$fresh"
rm -rf "case.mbtiles" "case_copy.mbtiles" "built.mbtiles" "replayed.mbtiles" "pack.bin"
