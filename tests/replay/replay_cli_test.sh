#!/usr/bin/env bash
# `tinyphong replay` on bad input: a partial word, an unknown opcode, a truncated command, a stream
# cut at a command's boundary (no end_frame at its end) and a refused value each give a message
# naming the file (and the word offset and the device's error for the stream errors) and a
# non-zero exit, as does a command asking for more than replay's memory limit (unless an earlier
# command fails first) and a file over the limit of a command file; a good stream replays and
# hashes. And `tinyphong record`'s outputs: two scenes of one name are refused, a failed write
# keeps the old stream, an existing PATH.part is refused and left alone, a symbolic link stays a
# link and the file it names gets the stream.
# Usage: replay_cli_test.sh TINYPHONG SCENES_DIR
set -euo pipefail
tp=$1 scenes=$2
work=$(mktemp -d)
trap 'rm -rf "$work"' EXIT
fail=0

"$tp" record "$scenes/triangle.json" --method gouraud --size 160x120 -o "$work/good.tpcmd" >/dev/null
"$tp" replay "$work/good.tpcmd" --hash -o "$work/good.png" | grep -qE '^[0-9a-f]{16}  .*good.tpcmd$' ||
  { echo "FAIL: a good stream did not print a hash"; fail=1; }

# expect NAME FILE REGEX: replay must exit non-zero and print REGEX on stderr.
expect() {
  local name=$1 file=$2 regex=$3 out status=0
  out=$("$tp" replay "$file" --hash 2>&1 >/dev/null) || status=$?
  if [ "$status" -eq 0 ]; then
    echo "FAIL: $name: exit status 0"; fail=1
  elif ! grep -qE -- "$regex" <<<"$out"; then
    echo "FAIL: $name: message '$out' does not match '$regex'"; fail=1
  else
    echo "ok: $name: $out"
  fi
}

# A file that is not a whole number of words.
head -c -2 "$work/good.tpcmd" > "$work/partial.tpcmd"
expect partial-word "$work/partial.tpcmd" "partial.tpcmd: .* not a whole number of 32-bit words"

# An unknown opcode in the first header (word 0).
cp "$work/good.tpcmd" "$work/opcode.tpcmd"
printf '\x63\x00' | dd of="$work/opcode.tpcmd" bs=1 seek=0 conv=notrunc status=none
expect unknown-opcode "$work/opcode.tpcmd" "opcode.tpcmd: command unknown opcode 99 at word 0 failed: bad opcode"

# A stream cut inside its last-but-one command (the draw): a whole number of words.
words=$(( $(stat -c %s "$work/good.tpcmd") / 4 ))
head -c $(( 4 * (words - 2) )) "$work/good.tpcmd" > "$work/cut.tpcmd"
expect truncated "$work/cut.tpcmd" "cut.tpcmd: command draw at word $(( words - 4 )) failed: bad command length"

# Streams cut at a command's boundary ran, and their frame so far passed for the frame (found by
# review, 2026-12-07): without the last command, end_frame, and with the first command alone.
head -c -4 "$work/good.tpcmd" > "$work/no-end.tpcmd"
expect no-end-frame "$work/no-end.tpcmd" \
  "no-end.tpcmd: the stream ends with draw at word $(( words - 4 )), not end_frame: no whole frame \(a truncated file\?\)"
head -c 20 "$work/good.tpcmd" > "$work/viewport-only.tpcmd"
expect viewport-only "$work/viewport-only.tpcmd" \
  "viewport-only.tpcmd: the stream ends with set_viewport at word 0, not end_frame"

# A refused value: the viewport's width (word 1) = 5000.
cp "$work/good.tpcmd" "$work/wide.tpcmd"
printf '\x88\x13\x00\x00' | dd of="$work/wide.tpcmd" bs=1 seek=4 conv=notrunc status=none
expect refused-value "$work/wide.tpcmd" "wide.tpcmd: command set_viewport at word 0 failed: viewport too large"

# Three words asking for 2^24 vertices and 2^26 indices: refused at that command, with what it
# needs, before a block that large is allocated.
printf '\x02\x00\x02\x00\x00\x00\x00\x01\x00\x00\x00\x04' > "$work/huge.tpcmd"
expect huge-capacity "$work/huge.tpcmd" "huge.tpcmd: command set_buffer_capacity at word 0 failed: out of device memory \(it needs [0-9]+ bytes, more than replay's limit of 1073741824\)"
# The same after an unknown opcode: the stream's first fault is the one reported.
{ printf '\x63\x00\x00\x00'; cat "$work/huge.tpcmd"; } > "$work/fault-first.tpcmd"
expect fault-first "$work/fault-first.tpcmd" "fault-first.tpcmd: command unknown opcode 99 at word 0 failed: bad opcode"

# A file over the limit of a command file (64 MiB; sparse, so it costs no disk), refused before
# more of it is read: /dev/zero would otherwise be read until memory ran out. The files after it
# are still replayed.
truncate -s $(( (64 << 20) + 4 )) "$work/large.tpcmd"
expect too-large "$work/large.tpcmd" "large.tpcmd: larger than 67108864 bytes \(the limit of a command file\)"
status=0
out=$("$tp" replay "$work/large.tpcmd" "$work/good.tpcmd" --hash 2>/dev/null) || status=$?
if [ "$status" -eq 0 ] || ! grep -qE '^[0-9a-f]{16}  .*good.tpcmd$' <<<"$out"; then
  echo "FAIL: after a file over the limit, the next was not replayed (status $status): $out"; fail=1
fi

# record: two scenes whose files share a name would write one stream; refused, nothing written.
mkdir -p "$work/a" "$work/b" "$work/dir"
cp "$scenes/triangle.json" "$work/a/x.json"
cp "$scenes/triangle.json" "$work/b/x.json"
status=0
out=$("$tp" record "$work/a/x.json" "$work/b/x.json" --dir "$work/dir" 2>&1 >/dev/null) || status=$?
if [ "$status" != 2 ] || ! grep -q "a/x.json and .*b/x.json would both be recorded to .*dir/x.tpcmd" <<<"$out" ||
   [ -n "$(ls -A "$work/dir")" ]; then
  echo "FAIL: two scenes of one name: status $status, '$out', dir holds '$(ls -A "$work/dir")'"; fail=1
else
  echo "ok: two scenes of one name: $out"
fi
# record replaces a stream whole or not at all: a write that fails part-way (here the file size
# limit, 0 blocks) leaves the old file and no PATH.part.
cp "$work/good.tpcmd" "$work/kept.tpcmd"
status=0
out=$(trap '' XFSZ; ulimit -f 0
      "$tp" record "$scenes/triangle.json" --method kb -o "$work/kept.tpcmd" 2>&1 >/dev/null) || status=$?
if [ "$status" = 0 ] || ! grep -q "kept.tpcmd: cannot write: File too large$" <<<"$out" ||
   ! cmp -s "$work/good.tpcmd" "$work/kept.tpcmd" || [ -e "$work/kept.tpcmd.part" ]; then
  echo "FAIL: a failed write: status $status, '$out', the old stream changed or PATH.part left"
  fail=1
else
  echo "ok: a failed write keeps the old stream and leaves no PATH.part: $out"
fi
# A PATH.part that is there already (left by an interrupted record, or a link that would send the
# words elsewhere) is refused and left as it was.
victim=$work/victim
echo victim > "$victim"
for stale in directory link; do
  rm -rf "$work/kept.tpcmd.part"
  if [ $stale = directory ]; then mkdir "$work/kept.tpcmd.part"; else ln -s "$victim" "$work/kept.tpcmd.part"; fi
  status=0
  out=$("$tp" record "$scenes/triangle.json" --method kb -o "$work/kept.tpcmd" 2>&1 >/dev/null) || status=$?
  left=0
  if [ $stale = directory ]; then [ -d "$work/kept.tpcmd.part" ] || left=1
  else [ -L "$work/kept.tpcmd.part" ] && [ "$(cat "$victim")" = victim ] || left=1; fi
  if [ "$status" = 0 ] || ! grep -q "kept.tpcmd.part exists" <<<"$out" || [ $left = 1 ] ||
     ! cmp -s "$work/good.tpcmd" "$work/kept.tpcmd"; then
    echo "FAIL: a $stale at PATH.part: status $status, '$out', or a file changed"; fail=1
  else
    echo "ok: a $stale at PATH.part is refused, nothing changed: $out"
  fi
done
rm -rf "$work/kept.tpcmd.part"
ln -s "$work/target.tpcmd" "$work/link.tpcmd"
"$tp" record "$scenes/triangle.json" --method gouraud --size 160x120 -o "$work/link.tpcmd" >/dev/null
if [ ! -L "$work/link.tpcmd" ] || ! cmp -s "$work/good.tpcmd" "$work/target.tpcmd"; then
  echo "FAIL: a symbolic link was replaced, or its target does not hold the stream"; fail=1
else
  echo "ok: through a symbolic link: the link kept, the file it names holds the stream"
fi

[ $fail -eq 0 ] && echo "replay CLI errors: all as expected"
exit $fail
