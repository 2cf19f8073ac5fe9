#!/usr/bin/env bash
# scripts/target-setup-split.py on the m3-Os replay image: its two parts and what neither reaches
# must hold all the firmware's code of the link map (as scripts/map_sizes.py reads it), the graph
# must reach every function, and functions must fall on the side they belong to: the methods'
# set-up and what only it calls (kb-adaptive's refinement, Bishop-Weimer's expansion) on the
# set-up's, the commands, the span loops and the exact shading that Phong's spans share with
# kb-adaptive's set-up on the device's. So the table of docs/TARGET.md ("Nor by set-up on the
# host") counts all the code, split where the calls are.
#   check_setup_split.sh TARGET_SETUP_SPLIT.py MAP_SIZES.py BUILD_DIR
set -euo pipefail
table=$(python3 "$1" --build "$3" --list)
head -4 <<<"$table"
code=$(sed -n 's/^firmware code of .*: \([0-9]*\) bytes in .*/\1/p' <<<"$table")
want=$(python3 "$2" "$3/target/m3-Os-replay.map" | awk '$1 == ".text" && $2 == "firmware" { print $3 }')
if [ -z "$code" ] || [ "$code" != "$want" ]; then
  echo "FAIL: the script counts ${code:-no} bytes of firmware code; the image's map has $want"
  exit 1
fi
neither=$(sed -n 's/^  reached from neither: \([0-9]*\) bytes.*/\1/p' <<<"$table")
[ "$neither" = 0 ] || { echo "FAIL: ${neither:-no figure for the} bytes reached from neither side"; exit 1; }
listed=$(awk '$1 ~ /^(device|setup|neither)$/ { sum += $2 } END { print sum + 0 }' <<<"$table")
[ "$listed" = "$code" ] || { echo "FAIL: the listed functions hold $listed bytes, not $code"; exit 1; }
side() {  # side FUNCTION-PREFIX WANT: every listed function whose name starts so is on WANT's side
  local found
  # a list line is "SIDE BYTES NAME": NAME starts after the two fields and their spaces
  found=$(awk -v f="$1" '$1 ~ /^(device|setup|neither)$/ && index($0, f) == length($1 $2) + 3 {
    print $1 }' <<<"$table" | sort -u)
  [ -n "$found" ] || { echo "FAIL: no function $1"; exit 1; }
  [ "$found" = "$2" ] || { echo "FAIL: $1 is on the $(tr '\n' ' ' <<<"$found")side, not the $2 side"; exit 1; }
}
side 'tp::fw::Device::execute_one(' device
side 'tp::fw::GouraudMethod::linear_span(' device
side 'tp::fw::PointShader::radiance(' device
side 'tp::fw::GouraudMethod::setup(' setup
side 'tp::fw::kb::KbOneVectorMethod::setup(' setup
side 'tp::fw::kb::KbAdaptiveMethod::add_leaf(' setup
side 'tp::fw::BishopWeimerMethod::expand(' setup
echo "firmware code $code bytes, as the replay image's map; every function reached, on its side"
