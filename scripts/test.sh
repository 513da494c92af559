#!/usr/bin/env bash
# Installs what is missing, builds, runs every test and prints a summary.
#   SEAMAP_WERROR=1 scripts/test.sh     compiler warnings are errors (scripts/build.sh; CI: .ci/run)
set -euo pipefail
root="$(cd "$(dirname "$0")/.." && pwd)"
build="${SEAMAP_BUILD_DIR:-$root/build}"
"$root/scripts/setup.sh"
"$root/scripts/build.sh"

cd "$build"
# Each randomised test's budget (tests/testing/fuzz.h); the seed is printed on failure.
export SEAMAP_FUZZ_SECONDS="${SEAMAP_FUZZ_SECONDS:-2}"
set +e
# A test that fails is run once more (a browser test's waits can run out on a
# loaded 2-core machine); a real failure fails both times, and the summary names
# every test that needed the second run, so a flake is seen, not hidden.
ctest --output-on-failure -j"$(nproc)" --timeout 600 --repeat until-pass:2 2>&1 | tee "$build/ctest.log"
status=${PIPESTATUS[0]}
set -e
total=$(grep -oE 'tests failed out of [0-9]+' "$build/ctest.log" | grep -oE '[0-9]+$' || echo 0)
failed=$(grep -oE '[0-9]+ tests failed' "$build/ctest.log" | grep -oE '^[0-9]+' || echo 0)
echo
echo "summary: $((total - failed)) passed, $failed failed"
reran=$(grep -E '\*\*\*(Failed|Timeout)' "$build/ctest.log" | sed -E 's/.*Test +#[0-9]+: ([^ ]+).*/\1/' | sort -u | tr '\n' ' ' || true)
[ -z "$reran" ] || echo "failed at least once (run again): $reran"
exit "$status"
