#!/usr/bin/env bash
# Sets up the operator console and its browser test, and only what is missing:
# npm packages (leaflet, pmtiles, playwright-core), Debian's chromium, and Leaflet
# and pmtiles copied into web/vendor/ so the console works offline. Quick when all is present.
set -euo pipefail
cd "$(dirname "$0")/.."

if ! command -v npm >/dev/null 2>&1; then
  echo "setup_web: npm not found (install nodejs and npm)" >&2
  exit 1
fi

# npm packages: install when node_modules is missing or older than the lock.
stamp=node_modules/.package-lock.json
if [[ ! -d node_modules/leaflet || ! -d node_modules/pmtiles || ! -d node_modules/playwright-core || ! -f $stamp || package-lock.json -nt $stamp ]]; then
  echo "setup_web: npm ci"
  npm ci --no-audit --no-fund --loglevel=error
fi

# Chromium for the end-to-end test (playwright-core downloads no browser).
if [[ ! -x /usr/bin/chromium ]]; then
  echo "setup_web: installing chromium"
  sudo=""
  [[ $(id -u) -ne 0 ]] && sudo="sudo"
  $sudo apt-get update -qq
  DEBIAN_FRONTEND=noninteractive $sudo apt-get install -y -qq --no-install-recommends chromium >/dev/null
fi

# Leaflet served from /vendor/leaflet/ (no CDN).
src=node_modules/leaflet/dist
dst=web/vendor/leaflet
if [[ ! -f $dst/leaflet.js || $src/leaflet.js -nt $dst/leaflet.js || ! -d $dst/images ]]; then
  mkdir -p "$dst"
  cp "$src/leaflet.js" "$src/leaflet.css" "$dst/"
  rm -rf "$dst/images"
  cp -r "$src/images" "$dst/images"
fi
# The PMTiles reader for web/pmtiles.html (a mission on a static host).
if [[ ! -f web/vendor/pmtiles/pmtiles.js || node_modules/pmtiles/dist/pmtiles.js -nt web/vendor/pmtiles/pmtiles.js ]]; then
  mkdir -p web/vendor/pmtiles
  cp node_modules/pmtiles/dist/pmtiles.js web/vendor/pmtiles/
fi
echo "setup_web: console packages present"
