#!/usr/bin/env bash
# Every test, from a fresh Debian 12 machine: dependencies, configure, build, test — the
# regular (dev) build, the sanitizer (ASan + UBSan) build and the fuzz targets (clang's
# libFuzzer: the committed corpora, then 60 s of fuzzing per target; docs/FUZZING.md). The
# dev build's tests include the Cortex-M images under QEMU (label target; docs/TARGET.md).
# Options: --fast   only tests labelled "fast" (skips slow sweeps, the browser suite, the
#                   Cortex-M images and the 60 s fuzzing runs; the fuzz corpora still run)
#          --preset P  only that preset (dev, sanitize, fuzz or release)
set -euo pipefail
cd "$(dirname "$0")/.."
label_args=()
presets=(dev sanitize fuzz)
while [ $# -gt 0 ]; do
  case "$1" in
    --fast) label_args=(-L fast) ;;
    --preset) presets=("$2"); shift ;;
    *) echo "usage: scripts/test.sh [--fast] [--preset dev|sanitize|fuzz|release]"; exit 2 ;;
  esac
  shift
done
bash scripts/install-deps.sh
[ -x scripts/install-node-deps.sh ] && bash scripts/install-node-deps.sh
jobs=$(nproc)
for preset in "${presets[@]}"; do
  echo "=== $preset: configure and build"
  cmake --preset "$preset" >/dev/null
  cmake --build --preset "$preset" -j "$jobs"
  echo "=== $preset: test"
  ctest --preset "$preset" "${label_args[@]}"
done
