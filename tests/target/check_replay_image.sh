#!/usr/bin/env bash
# The replay image (target/replay.cpp) run under QEMU on streams it reads from the host:
#   check_replay_image.sh [--all] QEMU MACHINE IMAGE TP_HOST_HASH TINYPHONG WORKDIR STREAM...
# For each STREAM, read whole and cut every 97 words and every word (--chunk), the image's hash
# must be the x86 device's (tp_host_hash), its stack mark at most 4 KiB. With --all (for one of the images, which share
# replay.cpp), also: the PPM it writes must hold the pixels of `tinyphong replay -o` (its PNG read
# back by oiiotool); the first STREAM cut inside a command past its middle, and with that
# command's opcode made unknown, read 5 words at a time, must stop at the word where the host's
# replay stops, with the device's error code; a missing file, a partial word, a failing read and
# a bad --chunk must fail.
set -uo pipefail
all=0
if [ "${1:-}" = --all ]; then
  all=1
  shift
fi
qemu=$1 machine=$2 image=$3 host_hash=$4 tinyphong=$5 work=$6
shift 6
mkdir -p "$work"
fail=0
run() {  # run ARGS: the image's output; its exit status in $status
  out=$(timeout 120 "$qemu" -M "$machine" -nographic -monitor none \
          -semihosting-config enable=on,target=native -kernel "$image" -append "$*" </dev/null 2>&1)
  status=$?
}
expect() {  # expect WHAT CONDITION...
  local what=$1
  shift
  if "$@"; then echo "ok: $what"; else echo "FAIL: $what"; echo "$out" | tail -n 4; fail=1; fi
}
# A PPM's size and pixel bytes: its header's three numbers, then everything after the one
# whitespace byte that ends the header (nothing if it is not a binary PPM).
pixels() {
  python3 -c 'import re, sys; d = open(sys.argv[1], "rb").read()
m = re.match(rb"P6\s+(\d+)\s+(\d+)\s+(\d+)\s", d)
sys.stdout.buffer.write(b" ".join(m.groups()) + b"\n" + d[m.end():] if m else b"")' "$1"
}
for stream in "$@"; do
  name=$(basename "$(dirname "$stream")")/$(basename "$stream")
  want=$("$host_hash" "$stream" | cut -d' ' -f1)
  for chunk in 16384 97 1; do
    ppm=""
    [ $all = 1 ] && ppm=$work/target.ppm
    run "$stream" $ppm --chunk $chunk
    got=$(awk -v f="$stream" '$1 == "stream" && $2 == f { print $3 }' <<<"$out")
    expect "$name, read $chunk words at a time: hash $got, host $want" \
      test "$status" = 0 -a "$got" = "$want"
    # Issue 12's stack budget for a small part, as run_image.sh holds the other images to it.
    stack=$(awk '/^stack high-water mark/ { print $4 }' <<<"$out")
    expect "... stack high-water mark ${stack:-?} bytes, at most 4096" test "${stack:-99999}" -le 4096
  done
  [ $all = 1 ] || continue
  "$tinyphong" replay "$stream" -o "$work/host.png" >/dev/null &&
    oiiotool "$work/host.png" --ch R,G,B -o "$work/host.ppm" ||
    { echo "FAIL: the host's frame of $name"; fail=1; continue; }
  expect "$name: the PPM's pixels are the host's frame" \
    test -n "$(pixels "$work/target.ppm" | head -c 1)" -a \
         "$(pixels "$work/target.ppm" | sha256sum)" = "$(pixels "$work/host.ppm" | sha256sum)"
done
[ $all = 1 ] || exit $fail
# Faults: the host's replay names the word where it stopped ("... at word N failed: ...").
# cut: the stream up to two words into the first command past its middle that has two payload
# words or more; bad-opcode: the stream with that command's opcode made unknown.
python3 -c 'import sys; d = bytearray(open(sys.argv[1], "rb").read()); at = 0
size = lambda at: int.from_bytes(d[4 * at + 2:4 * at + 4], "little")
while at < len(d) // 8 or size(at) < 2: at += 1 + size(at)
open(sys.argv[2], "wb").write(d[:4 * at + 8])
d[4 * at:4 * at + 2] = (0x7777).to_bytes(2, "little"); open(sys.argv[3], "wb").write(d)' \
  "$1" "$work/cut.tpcmd" "$work/bad-opcode.tpcmd"
for fault in cut bad-opcode; do
  f=$work/$fault.tpcmd
  host_at=$("$tinyphong" replay --hash "$f" 2>&1 | sed -n 's/.* at word \([0-9]*\) failed: .*/\1/p')
  code=2
  [ "$fault" = bad-opcode ] && code=1
  run "$f" --chunk 5
  expect "$fault, read 5 words at a time: stops at word ${host_at:-?} with error $code" \
    grep -qx "stream $f error $code at word ${host_at:-none}" <<<"$out"
  expect "... and exits with failure" test "$status" = 1
done
run "$work/missing.tpcmd"
expect "a missing file: cannot open, failure" \
  test "$status" = 1 -a "$(grep -c "missing.tpcmd: cannot open" <<<"$out")" = 1
# A file that ends inside a word runs nothing, as on the host; a read that fails (a directory:
# QEMU opens it, gives its length, and its reads fail) is not taken for the file's end.
head -c -2 "$1" > "$work/partial.tpcmd"
run "$work/partial.tpcmd"
expect "a partial word: refused before any command runs, failure" \
  test "$status" = 1 -a "$(grep -c "partial.tpcmd: [0-9]* bytes is not a whole number of 32-bit words" <<<"$out")" = 1 -a \
       "$(grep -c "^stream .* error\|^stream [^ ]* [0-9a-f]\{16\}$" <<<"$out")" = 0
mkdir -p "$work/a-directory"
size=$(stat -c %s "$work/a-directory")
if [ "$size" -gt 0 ] && [ $((size % 4)) = 0 ]; then  # ext4 and tmpfs; not XFS (6) or btrfs (0)
  run "$work/a-directory"
  expect "a read that fails: read error after 0 of $size bytes, failure" \
    test "$status" = 1 -a "$(grep -c "a-directory: read error after 0 of $size bytes" <<<"$out")" = 1
else
  echo "not run: a read that fails (a directory here is $size bytes, not a whole number of words)"
fi
run "$1" --chunk 0
expect "--chunk 0: refused, failure" \
  test "$status" = 1 -a "$(grep -c "^--chunk: a count of words" <<<"$out")" = 1
exit $fail
