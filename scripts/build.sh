#!/usr/bin/env bash
# Configures and builds SeaMap (Release) into build/. Used by the other scripts.
set -euo pipefail
root="$(cd "$(dirname "$0")/.." && pwd)"
build="${SEAMAP_BUILD_DIR:-$root/build}"
cmake -S "$root" -B "$build" -DCMAKE_BUILD_TYPE=Release >/dev/null
cmake --build "$build" -j"$(nproc)" 2>&1 | grep -vE '^\[ *[0-9]+%\]|^Consolidate|^Scanning' || true
test -x "$build/seamap" || { echo "build: seamap was not built" >&2; exit 1; }
echo "build: $build/seamap"
