#!/usr/bin/env bash
# Runs a Cortex-M image under QEMU and compares every framebuffer hash it prints with the x86
# device's hash of the same stream (what `tinyphong replay --hash` prints, written to HASHES by
# the fixture host_hashes.sh as "HASH  FILE" lines).
#   run_image.sh QEMU MACHINE IMAGE HASHES TIMEOUT_S NAME=STREAM.tpcmd...
# Each NAME must appear as "stream NAME HASH" in the image's output, in order. Prints
# "hash mismatch: NAME ..." for each difference; exits 0 iff QEMU exited 0, printed "done",
# every hash matched and the stack's high-water mark is within 4 KiB.
set -uo pipefail
qemu=$1 machine=$2 image=$3 hash_file=$4 timeout_s=$5
shift 5
out=$(timeout "$timeout_s" "$qemu" -M "$machine" -nographic -monitor none \
        -semihosting-config enable=on,target=native -kernel "$image" </dev/null 2>&1)
status=$?
echo "$out" | head -n 1
fail=0
if [ $status -ne 0 ]; then
  echo "FAIL: $qemu -M $machine exited with status $status (124: timeout after ${timeout_s} s)"
  echo "$out" | tail -n 5
  fail=1
fi
grep -qx "done" <<<"$out" || { echo "FAIL: the image did not print 'done'"; fail=1; }
# The stack's high-water mark over all the streams (the image paints its free stack first):
# issue 12's budget for a small part is 4 KiB. The marks measured: docs/TARGET.md, "Stack".
stack_limit=4096
stack=$(awk '/^stack high-water mark/ { print $4 }' <<<"$out")
if [ -z "$stack" ]; then
  echo "FAIL: the image did not print its stack high-water mark"
  fail=1
else
  echo "stack high-water mark: $stack bytes (limit $stack_limit)"
  [ "$stack" -le "$stack_limit" ] || { echo "FAIL: stack $stack bytes > $stack_limit"; fail=1; }
fi
# The host's hashes ("HASH  FILE" lines).
hashes=""
if [ -r "$hash_file" ]; then
  hashes=$(cat "$hash_file")
else
  echo "FAIL: no host hashes in $hash_file (the fixture target.host_hashes.* did not run)"
  fail=1
fi
matched=0
for pair in "$@"; do
  name=${pair%%=*} stream=${pair#*=}
  host=$(awk -v f="$stream" '$2 == f { print $1; exit }' <<<"$hashes")
  target=$(awk -v n="$name" '$1 == "stream" && $2 == n { $1 = ""; $2 = ""; sub(/^ +/, ""); print; exit }' <<<"$out")
  if [ -z "$host" ]; then
    echo "FAIL: the host did not hash $stream"
    fail=1
  elif [ "$target" != "$host" ]; then
    echo "hash mismatch: $name: target '${target:-<missing>}', host $host ($stream)"
    fail=1
  else
    matched=$((matched + 1))
  fi
done
echo "$machine $(basename "$image"): $matched of $# streams bit-identical to the host"
exit $fail
