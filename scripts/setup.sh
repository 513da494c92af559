#!/usr/bin/env bash
# Installs what SeaMap needs on Debian, and only what is missing: quick when
# everything is already there. Called by demo.sh, test.sh and bench.sh.
set -euo pipefail

packages=(
  build-essential cmake pkg-config git
  libopencv-dev libeigen3-dev libcpp-httplib-dev libevent-dev nlohmann-json3-dev
  libpng-dev libdeflate-dev libjpeg62-turbo-dev libsqlite3-dev sqlite3 libproj-dev proj-data libgtest-dev
  libceres-dev   # pose graphs (core/trajectory), the stereo pose's joint refinement (core/stereo)
  libopencv-contrib-dev   # surface_matching: the ICP baseline of stereo-locate (core/stereo)
  zlib1g-dev     # gzip of the live event stream (server/gzip_stream)
  gdal-bin   # tests open our MBTiles with gdalinfo
  libgdal-dev   # Cloud-Optimised GeoTIFF export (core/export)
  python3-onnx   # tests/fixtures/make_yolo_fixtures.py (the recogniser's tiny test models)
  clang-format   # scripts/check_format.sh (CI: .ci/run)
)
command -v npm >/dev/null 2>&1 || packages+=(nodejs npm)  # the console's Leaflet and the browser test
if [[ "${SEAMAP_BENCH:-0}" == 1 ]]; then
  packages+=(valgrind nginx-light wrk)  # profiling; the serving benchmark's reference server and load
fi
if [[ "${SEAMAP_TRAIN:-0}" == 1 ]]; then  # scripts/train_detector.py only (Debian's /usr/bin/python3)
  packages+=(python3-torch python3-torchvision python3-onnx python3-opencv)
fi

missing=()
for p in "${packages[@]}"; do
  dpkg-query -W -f='${Status}' "$p" 2>/dev/null | grep -q "install ok installed" || missing+=("$p")
done

if ((${#missing[@]})); then
  echo "setup: installing ${missing[*]}"
  sudo=""
  [[ $(id -u) -ne 0 ]] && sudo="sudo"
  $sudo apt-get update -qq
  DEBIAN_FRONTEND=noninteractive $sudo apt-get install -y -qq --no-install-recommends "${missing[@]}" >/dev/null
fi
echo "setup: system packages present"

# The console: Leaflet vendored into web/, playwright-core and Chromium for its test.
"$(dirname "$0")/setup_web.sh"
