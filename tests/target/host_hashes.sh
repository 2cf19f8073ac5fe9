#!/usr/bin/env bash
# The x86 device's framebuffer hash of each stream, for the image tests to compare with
# (run_image.sh): one run of tp_host_hash (host_hash.cpp: the lines `tinyphong replay --hash`
# prints) over STREAMS, written to OUT as "HASH  FILE" lines.
#   host_hashes.sh TP_HOST_HASH OUT STREAM.tpcmd...
# A CTest fixture (tests/target/CMakeLists.txt): the images of three configurations run the same
# streams, so the host hashes each stream once per run instead of once per image. OUT is removed
# first and written whole or not at all, so a failed run cannot leave an earlier run's hashes.
set -euo pipefail
hasher=$1 out=$2
shift 2
rm -f "$out"
mkdir -p "$(dirname "$out")"
"$hasher" "$@" > "$out.partial"
lines=$(wc -l < "$out.partial")
if [ "$lines" -ne $# ]; then
  echo "FAIL: $lines hashes for $# streams ($hasher)"
  exit 1
fi
mv "$out.partial" "$out"
echo "$# streams hashed by the x86 device: $out"
