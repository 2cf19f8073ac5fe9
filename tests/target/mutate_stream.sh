#!/usr/bin/env bash
# The deliberately changed stream of the target tests: IN with the clear command's colour word
# XORed with 0x00800000 (red 0 <-> 128), written to OUT. The stream stays valid, so the image
# runs and prints a hash; the test then expects that hash to differ from the host's hash of IN.
#   mutate_stream.sh IN OUT
set -euo pipefail
in=$1 out=$2
python3 - "$in" "$out" <<'PY'
import struct, sys
data = open(sys.argv[1], "rb").read()
words = list(struct.unpack("<%dI" % (len(data) // 4), data))
at, changed = 0, 0
while at < len(words):
    op, length = words[at] & 0xFFFF, words[at] >> 16
    if op == 13:  # kClear
        words[at + 1] ^= 0x00800000
        changed += 1
    at += 1 + length
if changed != 1:
    sys.exit("mutate_stream: expected one clear command, found %d" % changed)
open(sys.argv[2], "wb").write(struct.pack("<%dI" % len(words), *words))
PY
