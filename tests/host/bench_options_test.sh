#!/usr/bin/env bash
# The bench programs' options on bad values, checked as the CLI's are (host/cli_options.hpp):
# a bad method or size is refused as the option it is, with exit status 2, before any scene is
# read. Found by review (2026-12-06): tinyphong-results aborted (SIGABRT) on a bad method, and
# both programs read --size with sscanf, so that 4294967360x64 rendered at 64 x 64.
# Usage: bench_options_test.sh TINYPHONG_DRAW TINYPHONG_RESULTS SCENES_DIR
set -euo pipefail
draw=$1 results=$2 scenes=$3
tri=$scenes/triangle.json
fail=0

# exits STATUS TEXT ARGS...: the command must exit with STATUS and print TEXT.
exits() {
  local want=$1 text=$2 out status=0
  shift 2
  out=$("$@" 2>&1 >/dev/null) || status=$?
  if [ "$status" -ne "$want" ] || ! grep -qF -- "$text" <<<"$out"; then
    echo "FAIL: $* : status $status (want $want), output '$out'"; fail=1
  else
    echo "ok: $*"
  fi
}

for size in 4294967360x64 10x20junk 0x10 4097x10 x; do
  exits 2 "--size: expected WIDTHxHEIGHT, each 1..4096, got '$size'" "$draw" "$tri" --size "$size"
  exits 2 "--size: expected WIDTHxHEIGHT, each 1..4096, got '$size'" \
    "$results" --scenes triangle --size "$size"
done
exits 2 "--method: unknown shading method 'bogus'" "$draw" "$tri" --method bogus
exits 2 "--methods: unknown shading method 'bogus'" "$results" --methods kb,bogus
exits 2 "--methods: no method named in ','" "$results" --methods , --reps 1
exits 2 "--frames" "$draw" "$tri" --frames 0
exits 2 "--reps" "$results" --reps 0
# A scene that does not load is the program's error, not an option's: exit status 1.
exits 1 "no-such-scene" "$results" --scenes no-such-scene --methods flat --reps 1

# Good values work: one frame at the given size, and a one-round table of two methods.
out=$("$draw" "$tri" --method kb --size 32x16) ||
  { echo "FAIL: tinyphong-draw --method kb --size 32x16 refused"; fail=1; }
grep -qF "drew triangle (32x16, kb)" <<<"$out" ||
  { echo "FAIL: tinyphong-draw drew something else: '$out'"; fail=1; }
out=$("$results" --scenes triangle --methods flat --size 32x16 --reps 1) ||
  { echo "FAIL: tinyphong-results --methods flat --size 32x16 refused"; fail=1; }
grep -qE "^\| flat \|" <<<"$out" && grep -qE "^\| gouraud \|" <<<"$out" ||
  { echo "FAIL: tinyphong-results' table lacks flat's or Gouraud's row: '$out'"; fail=1; }
# Found by review, 2026-12-07: no scene printed the header alone with exit 0, and a scene or
# method named twice printed its rows twice. Now refused, and each is shown once.
exits 2 "--scenes: no scene named in ','" "$results" --scenes , --methods flat --reps 1
out=$("$results" --scenes triangle,triangle --methods flat,flat --size 32x16 --reps 1)
[ "$(grep -cE "^\| flat \|" <<<"$out")" = 1 ] ||
  { echo "FAIL: tinyphong-results ran a scene or method named twice twice: '$out'"; fail=1; }

# Found by review, 2026-12-08. Whole numbers are decimal digits (CLI11 took 0x10 and " 3").
for v in 0x10 " 3" 1e3 1.5 nan; do
  exits 2 "--frames: a whole number in 1..100000 (decimal digits), got '$v'" "$draw" "$tri" --frames "$v"
  exits 2 "--reps: a whole number in 1..1000 (decimal digits), got '$v'" "$results" --reps "$v"
done
# Every scene is read before any is measured: a bad name last printed the tables before it, and
# a path was joined to scenes/ and read.
status=0
out=$("$results" --scenes triangle,bogus --methods flat --size 16x16 --reps 1 2>/dev/null) || status=$?
[ "$status" = 1 ] && [ -z "$out" ] ||
  { echo "FAIL: tinyphong-results with a bad scene last: status $status, '$out'"; fail=1; }
for name in ../scenes/triangle /etc/passwd .hidden; do
  exits 2 "--scenes: '$name' is not a scene name" "$results" --scenes "$name" --reps 1
done
# A report that cannot be written is an error, exit 1 (it was lost with exit 0).
for cmd in "$draw $tri --size 4x4" "$results --scenes triangle --methods flat --size 8x8 --reps 1"; do
  status=0
  err=$($cmd 2>&1 >/dev/full) || status=$?
  if [ "$status" != 1 ] || ! grep -qF "standard output: cannot write" <<<"$err"; then
    echo "FAIL: $cmd > /dev/full: status $status, '$err'"; fail=1
  else
    echo "ok: $cmd > /dev/full: status 1"
  fi
done

[ $fail -eq 0 ] && echo "bench option checks: all as expected"
exit $fail
