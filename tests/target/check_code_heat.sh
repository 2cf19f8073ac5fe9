#!/usr/bin/env bash
# scripts/target-code-heat.py runs (its runs' frames must equal the host's, which it checks
# itself), and the functions it counts cover the firmware's code: their bytes must equal the
# firmware code of the replay image's link map, as scripts/map_sizes.py reads it. So the table
# of docs/TARGET.md ("Nor by a slower form for the code that rarely runs") counts all the code.
# Two methods on one scene: a few seconds, not the table's 84 runs.
#   check_code_heat.sh TARGET_CODE_HEAT.py MAP_SIZES.py BUILD_DIR
set -euo pipefail
table=$(python3 "$1" --build "$3" --methods gouraud,kb --scenes triangle)
echo "$table"
code=$(sed -n 's/.*firmware code \([0-9]*\) bytes in .*/\1/p' <<<"$table")
want=$(python3 "$2" "$3/target/m3-Os-replay.map" | awk '$1 == ".text" && $2 == "firmware" { print $3 }')
if [ -z "$code" ] || [ "$code" != "$want" ]; then
  echo "FAIL: the script counts ${code:-no} bytes of firmware code; the image's map has $want"
  exit 1
fi
grep -q '^| never run |' <<<"$table" || { echo "FAIL: no table of shares"; exit 1; }
echo "firmware code $code bytes, as the replay image's map"
