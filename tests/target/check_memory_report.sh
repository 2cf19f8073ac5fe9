#!/usr/bin/env bash
# A method's memory block within a limit, as a Cortex-M image built with TP_MEMORY_REPORT prints
# it (target/main.cpp: "memory_required 160x120 rgb565 no-depth: ID=BYTES+Vv+Ii ..."): the port's
# own figure, its method states sized by its TP_MAX_LIGHTS (docs/TARGET.md, "A small part"). The
# block for VERTICES and INDICES (a mesh's buffer capacity): BYTES + V·VERTICES + I·INDICES (each
# buffer is rounded up to 8 bytes: 4 more for an odd number of indices).
#   check_memory_report.sh QEMU IMAGE METHOD_ID VERTICES INDICES LIMIT_BYTES
set -uo pipefail
qemu=$1 image=$2 id=$3 vertices=$4 indices=$5 limit=$6
out=$(timeout 60 "$qemu" -M mps2-an385 -nographic -monitor none \
        -semihosting-config enable=on,target=native -kernel "$image" </dev/null 2>&1)
line=$(grep -m 1 "^memory_required " <<<"$out")
if [ -z "$line" ]; then
  echo "FAIL: $image printed no memory_required line:"
  echo "$out" | head -n 5
  exit 1
fi
echo "$line"
entry=$(tr ' ' '\n' <<<"$line" | awk -F= -v id="$id" '$1 == id { print $2 }')
if ! [[ $entry =~ ^([0-9]+)\+([0-9]+)v\+([0-9]+)i$ ]]; then
  echo "FAIL: method $id is not in the report (not linked?), or its entry '$entry' is malformed"
  exit 1
fi
bytes=$((BASH_REMATCH[1] + BASH_REMATCH[2] * vertices + BASH_REMATCH[3] * indices))
if [ "$bytes" -gt "$limit" ]; then
  echo "FAIL: method $id needs $bytes bytes with $vertices vertices and $indices indices > limit $limit"
  exit 1
fi
echo "method $id: $bytes bytes with $vertices vertices and $indices indices <= limit $limit"
