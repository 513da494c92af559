#!/usr/bin/env bash
# Configures and builds SeaMap (Release) into build/. Used by the other scripts.
#   SEAMAP_WERROR=1 scripts/build.sh    compiler warnings are errors (CI: .ci/run)
set -euo pipefail
root="$(cd "$(dirname "$0")/.." && pwd)"
build="${SEAMAP_BUILD_DIR:-$root/build}"
werror=OFF
case "${SEAMAP_WERROR:-0}" in 1 | ON | on | true) werror=ON ;; esac
cmake -S "$root" -B "$build" -DCMAKE_BUILD_TYPE=Release -DSEAMAP_WERROR=$werror >/dev/null
log="$build/build.log"
if ! cmake --build "$build" -j"$(nproc)" >"$log" 2>&1; then
  grep -E "error|Error" "$log" | head -40 >&2
  echo "build: FAILED (full log: $log)" >&2
  exit 1
fi
grep -E "warning:" "$log" | head -20 || true
echo "build: $build/seamap"
