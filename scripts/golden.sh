#!/usr/bin/env bash
# Golden check of a change: builds the bench surveys (gray 696x520 JPEG x400,
# colour 1392x1040 JPEG x200, both to PNG and the colour one to JPEG tiles too)
# with the seamap of an earlier commit and with this checkout's, and prints
# how the maps differ (build/map_diff: tiles only in one, pixels whose
# coverage or value differ, by how much).
#   scripts/golden.sh COMMIT            e.g. scripts/golden.sh main~3
#   GOLDEN_OLD_CONFIG='{"key": value}'  settings added for the old build only
#                                       (to switch off what the change removed)
set -euo pipefail
root="$(cd "$(dirname "$0")/.." && pwd)"
build="${SEAMAP_BUILD_DIR:-$root/build}"
commit="${1:?usage: scripts/golden.sh COMMIT}"
sha="$(git -C "$root" rev-parse --short "$commit")"
out="$root/out/golden"
old_src="$out/src-$sha"
mkdir -p "$out"
"$root/scripts/build.sh" >/dev/null
if [[ ! -x "$old_src/build/seamap" ]]; then
  echo "golden: building $sha in $old_src"
  rm -rf "$old_src"
  git -C "$root" worktree add --detach --force "$old_src" "$sha" >/dev/null 2>&1
  cmake -S "$old_src" -B "$old_src/build" -DCMAKE_BUILD_TYPE=Release >/dev/null
  cmake --build "$old_src/build" -j"$(nproc)" --target seamap >/dev/null
fi
new="$build/seamap" old="$old_src/build/seamap"

simulate() {  # name, frames, extra simulate args
  [[ -f "$out/$1/nav.csv" ]] || "$new" simulate --out "$out/$1" --frames "$2" --force $3 >/dev/null 2>&1
}
simulate gray 400 "--image-format jpg"
simulate colour 200 "--color --width 1392 --height 1040 --pixel-pitch-um 6.45 --image-format jpg --texture-res 0.001"

status=0
compare() {  # survey, config json, label
  local cfg_new="$out/$1.$3.new.json" cfg_old="$out/$1.$3.old.json"
  echo "$2" >"$cfg_new"
  python3 -c "import json,sys; a=json.loads(sys.argv[1]); a.update(json.loads(sys.argv[2])); print(json.dumps(a))" \
    "$2" "${GOLDEN_OLD_CONFIG:-{\}}" >"$cfg_old"
  for side in old new; do
    local bin="$old" cfg="$cfg_old"
    [[ $side == new ]] && bin="$new" cfg="$cfg_new"
    "$bin" build --quiet --images "$out/$1/photo" --nav "$out/$1/nav.csv" --camera "$out/$1/camera.json" \
      --origin 43.1,131.9 --config "$cfg" --out "$out/$1.$3.$side.mbtiles" --overwrite >/dev/null
  done
  echo "$1, $3 ($sha -> this checkout):"
  "$build/map_diff" "$out/$1.$3.old.mbtiles" "$out/$1.$3.new.mbtiles" || status=1
}
compare gray '{"tile_format":"png"}' png
compare colour '{"tile_format":"png"}' png
compare colour '{"tile_format":"jpg"}' jpg
exit $status
