#!/usr/bin/env bash
# The firmware's code or read-only data within a budget (issue 12's for a small part, or the
# all-methods image's ceiling): fails, with the figure, when an image's firmware SECTION (.text or
# .rodata) exceeds BYTES. SECTION "flash" is everything the part's flash holds instead: the vector
# table, code and read-only data of every origin (firmware, port, libgcc, newlib), the embedded
# streams and their table left out. Summed from the image's link map by scripts/map_sizes.py
# (docs/TARGET.md, "Footprint").
#   check_budget.sh MAP_SIZES.py IMAGE.map SECTION BYTES
set -euo pipefail
sizes=$(python3 "$1" "$2")
if [ "$3" = flash ]; then
  what="flash (vectors, code and read-only data but the streams)"
  bytes=$(awk '/^flash in all / { print $NF }' <<<"$sizes")
else
  what="firmware $3"
  bytes=$(awk -v section="$3" '$1 == section && $2 == "firmware" { print $3 }' <<<"$sizes")
fi
if [ -z "$bytes" ]; then
  echo "FAIL: $2 has no $what line:"
  echo "$sizes"
  exit 1
fi
if [ "$bytes" -gt "$4" ]; then
  echo "FAIL: $what $bytes bytes > budget $4 ($2)"
  exit 1
fi
echo "$what $bytes bytes <= budget $4 ($2)"
