#!/usr/bin/env bash
# scripts/target-method-size.py's links are the build's own: its "every method" row must equal
# the firmware code and read-only data of the build's m3-Os image (which links every method),
# as scripts/map_sizes.py reads them from that image's link map; and it must give a row for every
# method of `tinyphong methods`. So the per-method figures of docs/TARGET.md ("Code by method")
# are comparable with the footprint table's.
#   check_method_size.sh TARGET_METHOD_SIZE.py MAP_SIZES.py BUILD_DIR IMAGE.map TINYPHONG
set -euo pipefail
table=$(python3 "$1" --build "$3")
echo "$table"
row=$(grep '^| every method |' <<<"$table") || { echo "FAIL: no 'every method' row"; exit 1; }
code=$(awk -F'|' '{ gsub(/[ ,]/, "", $3); print $3 }' <<<"$row")
rodata=$(awk -F'|' '{ gsub(/[ ,]/, "", $5); print $5 }' <<<"$row")
sizes=$(python3 "$2" "$4")
want_code=$(awk '$1 == ".text" && $2 == "firmware" { print $3 }' <<<"$sizes")
want_rodata=$(awk '$1 == ".rodata" && $2 == "firmware" { print $3 }' <<<"$sizes")
if [ "$code" != "$want_code" ] || [ "$rodata" != "$want_rodata" ]; then
  echo "FAIL: every method linked by the script: code $code, .rodata $rodata;" \
       "the build's image $4: code $want_code, .rodata $want_rodata"
  exit 1
fi
missing=0
for m in $("$5" methods | cut -f1); do
  case $m in flat | gouraud) grep -q "^| base: flat + gouraud |" <<<"$table" ;;
    *) grep -q "^| $m |" <<<"$table" ;;
  esac || { echo "FAIL: no row for $m"; missing=1; }
done
[ "$missing" = 0 ] || exit 1
echo "every method: code $code, .rodata $rodata bytes, as the build's image; every method has a row"
