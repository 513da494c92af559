#!/usr/bin/env bash
# Installs what SeaMap needs on Debian, and only what is missing: quick when
# everything is already there. Called by demo.sh, test.sh and bench.sh.
set -euo pipefail

packages=(
  build-essential cmake pkg-config git
  libopencv-dev libeigen3-dev libcpp-httplib-dev nlohmann-json3-dev
  libpng-dev libsqlite3-dev sqlite3 libproj-dev proj-data libgtest-dev
  gdal-bin   # tests open our MBTiles with gdalinfo
)
if [[ "${SEAMAP_BENCH:-0}" == 1 ]]; then
  packages+=(valgrind)
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
