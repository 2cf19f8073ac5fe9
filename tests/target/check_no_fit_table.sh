#!/usr/bin/env bash
# The firmware derives the Kuijk-Blake (a, b) by closed forms (firmware/cosn.hpp): no generated
# fit table (tables/cosn_fits.hpp) may be linked into a Cortex-M image. Fails, naming the symbols,
# if one is; also fails if the image has no Kuijk-Blake code at all (the check would be empty).
#   check_no_fit_table.sh NM IMAGE.elf
set -euo pipefail
nm=$1
image=$2
symbols=$("$nm" -C "$image")
if ! grep -q 'least_squares_params\|MaterialCoeffs::refresh' <<<"$symbols"; then
  echo "FAIL: $image holds no Kuijk-Blake (a, b) code: nothing to check"
  exit 1
fi
if grep 'tables::cosn_fits::' <<<"$symbols"; then
  echo "FAIL: $image links the fit tables above"
  exit 1
fi
echo "$image: no fit table linked"
