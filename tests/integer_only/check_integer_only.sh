#!/usr/bin/env bash
# Proves that fixedpoint/ and firmware/ are integer-only, three ways:
#   x86   : compile every firmware TU, plus one TU that includes every header, with
#           -mgeneral-regs-only: any float/double value in code that is compiled is an error.
#   arm   : compile the same for Cortex-M3 with soft float, link nothing, and fail if any
#           object references a soft-float helper (__aeabi_f*, __aeabi_d*, __addsf3, ...).
#   tokens: fail on the words float/double/long double or <cmath> outside comments, which
#           also covers templates that no TU instantiates.
# Usage: check_integer_only.sh MODE SOURCE_DIR GENERATED_DIR [--only] [extra.cpp ...]
# Extra files are checked as if they were firmware sources (the tests use this to show that
# the check fails when a float is introduced); with --only, they alone: the same test per unit,
# without compiling the firmware a second time (the rejects_float tests).
set -euo pipefail
mode=$1 src=$2 gen=$3
shift 3
only=false
if [ "${1:-}" = --only ]; then
  only=true
  shift
fi
work=$(mktemp -d)
trap 'rm -rf "$work"' EXIT

headers=$(cd "$src" && find fixedpoint firmware -name '*.hpp' | sort)
sources=$(cd "$src" && find firmware -name '*.cpp' | sort)
units=()
if ! $only; then
  all_headers_tu="$work/all_headers.cpp"
  for h in $headers; do echo "#include \"$h\""; done > "$all_headers_tu"
  units+=("$all_headers_tu")
  for s in $sources; do units+=("$src/$s"); done
else
  headers="" sources=""
fi
for e in "$@"; do units+=("$e"); done
[ ${#units[@]} -gt 0 ] || { echo "check_integer_only.sh: nothing to check"; exit 2; }

common=(-std=c++20 -O2 -fno-exceptions -fno-rtti -I"$src" -I"$gen" -Wall -Werror)
status=0
case "$mode" in
  x86)
    for u in "${units[@]}"; do
      if ! g++ "${common[@]}" -mgeneral-regs-only -c "$u" -o "$work/$(basename "$u").o" 2>"$work/err"; then
        echo "FAIL: $u uses floating point (or does not compile) under -mgeneral-regs-only:"
        head -n 20 "$work/err"
        status=1
      fi
    done
    ;;
  arm)
    command -v arm-none-eabi-g++ >/dev/null || { echo "arm-none-eabi-g++ missing: run scripts/install-deps.sh"; exit 1; }
    for u in "${units[@]}"; do
      obj="$work/$(basename "$u").o"
      if ! arm-none-eabi-g++ "${common[@]}" -mcpu=cortex-m3 -mthumb -mfloat-abi=soft -c "$u" -o "$obj" 2>"$work/err"; then
        echo "FAIL: $u does not compile for Cortex-M3:"; head -n 20 "$work/err"; status=1; continue
      fi
      helpers=$(arm-none-eabi-nm -u "$obj" | awk '{print $NF}' |
        grep -E '^(__aeabi_[fd]|__aeabi_[lu]*[fd]2|__aeabi_[iul]+2[fd]|__(add|sub|mul|div|neg|cmp|eq|ne|lt|le|gt|ge|unord)[sdt]f[23]|__(fix|fixuns|float|floatun|extend|trunc)[a-z]*[sdt]f|__pow|sqrt|sin|cos|exp|log|pow)' || true)
      if [ -n "$helpers" ]; then
        echo "FAIL: $u references soft-float helpers:"; echo "$helpers"; status=1
      fi
    done
    ;;
  tokens)
    for f in $headers $sources "$@"; do
      path=$f; [ -f "$path" ] || path="$src/$f"
      # Strip // and /* */ comments and string literals, then look for floating-point words and
      # literals (1.5, 2., .5, 1e3f are caught; identifiers like theta0.raw() are not).
      hits=$(sed -e 's://.*$::' "$path" | perl -0pe 's:/\*.*?\*/::gs; s/"(\\.|[^"\\])*"/""/g' |
             grep -nE '\b(float|double)\b|<cmath>|<math\.h>|\bstd::(sin|cos|tan|sqrt|pow|exp|log)\b|(^|[^A-Za-z0-9_.])[0-9]+\.[0-9]*([eE][-+]?[0-9]+)?[fFlL]?([^A-Za-z0-9_]|$)|(^|[^A-Za-z0-9_.])\.[0-9]+' || true)
      if [ -n "$hits" ]; then echo "FAIL: floating point in $f:"; echo "$hits" | head -n 5; status=1; fi
    done
    ;;
  *) echo "unknown mode $mode"; exit 2 ;;
esac
[ $status -eq 0 ] && echo "integer-only ($mode): ${#units[@]} units clean"
exit $status
