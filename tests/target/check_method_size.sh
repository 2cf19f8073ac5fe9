#!/usr/bin/env bash
# scripts/target-method-size.py's links are the build's own: its "every method" row must equal
# the firmware code and read-only data of the build's m3-Os image (which links every method),
# as scripts/map_sizes.py reads them from that image's link map; and it must give a row for every
# method of `tinyphong methods`. So the per-method figures of docs/TARGET.md ("Code by method")
# are comparable with the footprint table's. And its greedy --fill (docs/TARGET.md, "What fits a
# part") adds a method exactly when the image stays within the bytes given.
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

# --fill: from every method but two, within exactly the every-method image's code both are added
# (the last row is that image); one byte less and the last method is left out, the budget named.
all=$("$5" methods | cut -f1 | grep -v '^flat$\|^gouraud$' | paste -sd, -)
but_two=$(tr ',' '\n' <<<"$all" | grep -v '^kb-noskip$\|^kb-adaptive-exact$' | paste -sd, -)
but_one=$(tr ',' '\n' <<<"$all" | grep -v '^kb-adaptive-exact$' | paste -sd, -)
filled=$(python3 "$1" --build "$3" --methods "$but_two" --fill "$code")
echo "$filled"
last=$(grep '^| + ' <<<"$filled" | tail -1)
last_code=$(awk -F'|' '{ gsub(/[ ,]/, "", $3); print $3 }' <<<"$last")
if [ "$(grep -c '^| + ' <<<"$filled")" != 2 ] || [ "$last_code" != "$code" ] ||
  ! grep -q '^every method fits within' <<<"$filled"; then
  echo "FAIL: --fill $code from every method but two: not both added up to code $code"
  exit 1
fi
short=$(python3 "$1" --build "$3" --methods "$but_one" --fill $((code - 1)))
echo "$short"
count=$("$5" methods | wc -l)
pattern="^left out: 1 of $count methods; the cheapest next, kb-adaptive-exact, would make"
left=$(sed -n "s/$pattern \([0-9,]*\) bytes.*/\1/p" <<<"$short")
[ "${left//,/}" = "$code" ] ||
  { echo "FAIL: --fill $((code - 1)) did not leave kb-adaptive-exact out at $code bytes"; exit 1; }
echo "--fill: both added within $code bytes, the last left out within one byte less"
