#!/usr/bin/env bash
# scripts/target-code-heat.py on gouraud's and kb's triangle: it checks each run's frame against
# the host's and stops on a block that lies in no section of the image's code; here its
# functions must hold all the firmware's code of the replay image's link map (as
# scripts/map_sizes.py reads it), and their instructions must fall where the two methods run:
# Gouraud's span and kb's set-up run, Bishop-Weimer's expansion does not. So the tables of
# docs/TARGET.md ("Nor by a slower form for the code that rarely runs") count all the code, each
# function's own instructions. A few seconds, not the table's 84 runs.
#   check_code_heat.sh TARGET_CODE_HEAT.py MAP_SIZES.py BUILD_DIR QEMU
set -euo pipefail
table=$(python3 "$1" --build "$3" --qemu "$4" --methods gouraud,kb --scenes triangle --top 1000)
echo "$table"
code=$(sed -n 's/.*firmware code \([0-9]*\) bytes in .*/\1/p' <<<"$table")
want=$(python3 "$2" "$3/target/m3-Os-replay.map" | awk '$1 == ".text" && $2 == "firmware" { print $3 }')
if [ -z "$code" ] || [ "$code" != "$want" ]; then
  echo "FAIL: the script counts ${code:-no} bytes of firmware code; the image's map has $want"
  exit 1
fi
share() {  # the largest share of a run that the function takes, in %, from the --top table
  awk -F'|' -v f="\`$1\`" '{ gsub(/^ +| +$/, "", $4) } $4 == f { gsub(/[ %]/, "", $3); print $3 }' <<<"$table"
}
check() {  # check FUNCTION ran|idle
  local s
  s=$(share "$1")
  [ -n "$s" ] || { echo "FAIL: no row for $1"; exit 1; }
  if [ "$2" = ran ] && awk -v s="$s" 'BEGIN { exit !(s <= 0) }'; then
    echo "FAIL: $1 took no instructions"; exit 1
  fi
  if [ "$2" = idle ] && awk -v s="$s" 'BEGIN { exit !(s > 0) }'; then
    echo "FAIL: $1 took $s % of a run, though no run uses it"; exit 1
  fi
}
check tp::fw::GouraudMethod::linear_span ran
check tp::fw::kb::KbOneVectorMethod::setup ran
check tp::fw::BishopWeimerMethod::expand idle
echo "firmware code $code bytes, as the replay image's map; instructions where the methods run"
