#!/usr/bin/env bash
# Code and read-only data of the Cortex-M images by origin (firmware, port, libgcc, newlib),
# summed from each image's link map: the footprint table of docs/TARGET.md. The streams
# (section .streams) are not counted. Every method is linked into every image of a
# configuration, so one image per configuration is enough (kb-adaptive's, which every
# configuration has); m3-Os-small links only flat, gouraud and kb-adaptive, m3-Os-tiny flat, gouraud
# and kb for two lights, whose kb image is taken (target/CMakeLists.txt).
# Usage: bash scripts/target-size.sh [--build DIR]   (default build/release, already built)
set -euo pipefail
cd "$(dirname "$0")/.."
build=build/release
[ "${1:-}" = --build ] && build=$2
for cfg in m3-O2 m3-Os m7-O2 m3-Os-small m3-Os-tiny; do
  image=kb-adaptive
  [ $cfg = m3-Os-tiny ] && image=kb
  map=$build/target/$cfg-$image.map
  [ -f "$map" ] || { echo "target-size.sh: $map missing (build the release preset first)" >&2; exit 1; }
  echo "== $cfg ($map)"
  python3 scripts/map_sizes.py "$map"
done
