#!/usr/bin/env bash
# A Cortex-M image's symbols against a rule of issue 12: fails, naming them, if the image holds
# any symbol matching FORBIDDEN; fails too if it holds none matching NEEDED, the code the rule
# is about, since the check would then prove nothing. Both are extended regular expressions over
# `nm -C`'s output. Used by the no_fit_table and no_division_helper tests (CMakeLists.txt).
#   check_image_symbols.sh NM IMAGE.elf NEEDED FORBIDDEN WHAT
set -euo pipefail
nm=$1
image=$2
needed=$3
forbidden=$4
what=$5
symbols=$("$nm" -C "$image")
if ! grep -Eq "$needed" <<<"$symbols"; then
  echo "FAIL: $image holds no symbol matching '$needed': nothing to check"
  exit 1
fi
if grep -E "$forbidden" <<<"$symbols"; then
  echo "FAIL: $image links $what (the symbols above)"
  exit 1
fi
echo "$image: no $what linked"
