#!/usr/bin/env bash
# The firmware's code or read-only data within a budget (issue 12's for a small part, or the
# all-methods image's ceiling): fails, with the figure, when an image's firmware SECTION (.text or
# .rodata) exceeds BYTES. Summed from the image's link map by scripts/map_sizes.py (docs/TARGET.md,
# "Footprint").
#   check_budget.sh MAP_SIZES.py IMAGE.map SECTION BYTES
set -euo pipefail
sizes=$(python3 "$1" "$2")
bytes=$(awk -v section="$3" '$1 == section && $2 == "firmware" { print $3 }' <<<"$sizes")
if [ -z "$bytes" ]; then
  echo "FAIL: $2 has no firmware $3 line:"
  echo "$sizes"
  exit 1
fi
if [ "$bytes" -gt "$4" ]; then
  echo "FAIL: firmware $3 $bytes bytes > budget $4 ($2)"
  exit 1
fi
echo "firmware $3 $bytes bytes <= budget $4 ($2)"
