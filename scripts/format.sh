#!/usr/bin/env bash
# Formats the repository's C++ sources with its .clang-format, or checks them.
#
#   bash scripts/format.sh                 format every source in place
#   bash scripts/format.sh --check         list the sources that are not formatted; fail if any
#   bash scripts/format.sh --check FILE…   the same for the given files
#
# The style is clang-format 14's (Debian 12's clang-format package; other versions may format
# some constructs differently, so the check insists on 14). The CTest format.check runs --check.
set -euo pipefail
root="$(cd "$(dirname "$0")/.." && pwd)"
cf="${CLANG_FORMAT:-clang-format-14}"
if ! command -v "$cf" >/dev/null; then
  echo "format.sh: $cf not found (bash scripts/install-deps.sh installs it)" >&2
  exit 2
fi

check=false
if [[ "${1:-}" == --check ]]; then
  check=true
  shift
fi
files=("$@")
if [[ ${#files[@]} -eq 0 ]]; then
  cd "$root"
  mapfile -t files < <(find bench firmware fixedpoint host server tables target tests -type f \
                         \( -name '*.cpp' -o -name '*.hpp' \) -not -path '*/node_modules/*' | sort)
fi

if ! $check; then
  "$cf" -i --style=file "${files[@]}"
  echo "format.sh: formatted ${#files[@]} files"
  exit 0
fi
# One clang-format process for all the files (one per file took 20 s of CI, most of it starting
# the process): --dry-run reports each change it would make as "FILE:LINE:COL: warning: code
# should be clang-formatted"; its own failure (a missing file, say) is an error of this script.
report=$("$cf" --style=file --dry-run "${files[@]}" 2>&1) || {
  echo "format.sh: $cf failed:" >&2
  echo "$report" >&2
  exit 2
}
mapfile -t bad < <(sed -n 's/^\(.*\):[0-9]*:[0-9]*: warning: code should be clang-formatted.*/\1/p' \
                     <<<"$report" | sort -u)
for f in "${bad[@]}"; do echo "not formatted: $f (bash scripts/format.sh formats it)"; done
if [[ ${#bad[@]} -gt 0 ]]; then
  echo "format.sh: ${#bad[@]} of ${#files[@]} files not formatted" >&2
  exit 1
fi
echo "format.sh: all ${#files[@]} files formatted"
