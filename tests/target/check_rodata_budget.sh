#!/usr/bin/env bash
# The firmware's read-only data (tables, vtables, the registry's rows) within issue 12's budget
# for a small part: fails, with the figure, when an image's firmware .rodata exceeds BYTES.
# Summed from the image's link map by scripts/map_sizes.py (docs/TARGET.md, "Footprint").
#   check_rodata_budget.sh MAP_SIZES.py IMAGE.map BYTES
set -euo pipefail
sizes=$(python3 "$1" "$2")
bytes=$(awk '$1 == ".rodata" && $2 == "firmware" { print $3 }' <<<"$sizes")
if [ -z "$bytes" ]; then
  echo "FAIL: $2 has no firmware .rodata line:"
  echo "$sizes"
  exit 1
fi
if [ "$bytes" -gt "$3" ]; then
  echo "FAIL: firmware .rodata $bytes bytes > budget $3 ($2)"
  exit 1
fi
echo "firmware .rodata $bytes bytes <= budget $3 ($2)"
