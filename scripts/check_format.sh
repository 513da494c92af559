#!/usr/bin/env bash
# Checks that every tracked C++ file (*.cc, *.h) is formatted as .clang-format
# says, and prints those that are not (fix one with `clang-format -i FILE`).
# Exit status 1 when any is not. Run by .ci/run.
set -euo pipefail
cd "$(dirname "$0")/.."
if ! command -v clang-format >/dev/null 2>&1; then
  echo "check_format: clang-format not found (scripts/setup.sh installs it)" >&2
  exit 1
fi
set +e
report=$(git ls-files -z -- '*.cc' '*.h' | xargs -0 clang-format --style=file --dry-run --Werror 2>&1)
status=$?
set -e
if ((status == 0)); then
  echo "check_format: $(git ls-files -- '*.cc' '*.h' | wc -l) files formatted as .clang-format says"
  exit 0
fi
# "FILE:LINE:COL: error: code should be clang-formatted [-Wclang-format-violations]"
files=$(grep -E ': error: code should be clang-formatted' <<<"$report" | cut -d: -f1 | sort -u)
if [[ -z $files ]]; then  # clang-format itself failed (a bad .clang-format, an unreadable file)
  echo "$report" >&2
  echo "check_format: clang-format failed" >&2
  exit 1
fi
echo "check_format: not formatted as .clang-format says (clang-format -i FILE):" >&2
sed 's/^/  /' <<<"$files" >&2
exit 1
