#!/usr/bin/env bash
# Guest instructions per pixel written of the device's draw on the Cortex-M3 (QEMU mps2-an385),
# for every method and paper scene at the target suite's 160x120 (a benchmark, not a test;
# docs/TARGET.md). Runs the m3-O2-cost-METHOD images (target/main.cpp built with TP_COST) under
# `qemu-system-arm -icount shift=0`, where guest time advances exactly 1 ns per instruction:
# the image reads the MPS2's 25 MHz CMSDK timer around everything from the first draw on
# (draws, model-views, end_frame) and calibrates ticks against a loop of 2,000,000 known
# instructions (40 instructions per tick; so the figures have a resolution of 40 instructions
# per frame). Prints two markdown tables: instructions per pixel written, and the ratio to
# Gouraud; and the calls of the 64-bit division helpers (__aeabi_ldivmod, __aeabi_uldivmod),
# counted by wrappers linked into the cost images (target/divcount.S), whose own instructions (7
# per call) are taken out of the first table: one line when there are none (the firmware divides
# with fixedpoint/divide.hpp), else a table of the calls per pixel written.
#
# Usage: bash scripts/target-cost.sh [--build DIR] [--config CFG] [--methods m1,m2,...] [--full]
#   DIR: a configured and built tree with the target images (default build/release).
#   CFG: m3-O2 (the default), or a small part's build, m3-Os-small (flat, gouraud,
#   kb-adaptive) or m3-Os-tiny (flat, gouraud, kb; its scenes with at most two lights): their
#   CFG-cost-METHOD images, for the methods they link (target/parts.cmake).
#   --methods: default every method CFG links, in the order of DIR/target/CFG-cost-methods.txt
#   (written by target/CMakeLists.txt).
#   --full: the scenes at their own resolutions (512x512, 640x480; the m3-O2-cost-full-METHOD
#   images) instead of 160x120: per-triangle and per-span work weigh less there, so the
#   figures are nearer what a frame of the scene costs (about 90 s under -icount).
set -euo pipefail
cd "$(dirname "$0")/.."
build=build/release
kind=cost size=160x120 config=m3-O2 methods=
while [ $# -gt 0 ]; do
  case "$1" in
    --build) build=$2; shift 2 ;;
    --methods) methods=$2; shift 2 ;;
    --config) config=$2; shift 2 ;;
    --full) kind=cost-full size="the scenes' own resolutions"; shift ;;
    *) echo "usage: $0 [--build DIR] [--config CFG] [--methods m1,m2] [--full]" >&2; exit 2 ;;
  esac
done
command -v qemu-system-arm >/dev/null || { echo "target-cost.sh: qemu-system-arm missing (scripts/install-deps.sh)" >&2; exit 1; }
[ -d "$build" ] || { echo "target-cost.sh: no build tree $build (cmake --preset release && cmake --build --preset release)" >&2; exit 1; }
cmake --build "$build" --target tp_target_images >/dev/null
if [ -z "$methods" ]; then
  # Every method the configuration links, as target/CMakeLists.txt lists its cost images.
  list=$build/target/$config-cost-methods.txt
  [ -f "$list" ] || { echo "target-cost.sh: no cost images for $config ($list missing)" >&2; exit 1; }
  methods=$(cat "$list")
fi
tmp=$(mktemp -d)
trap 'rm -rf "$tmp"' EXIT
for m in ${methods//,/ }; do
  image=$build/target/$config-$kind-$m.elf
  [ -f "$image" ] || { echo "target-cost.sh: $image missing" >&2; exit 1; }
  timeout 600 qemu-system-arm -M mps2-an385 -icount shift=0 -nographic -monitor none \
    -semihosting-config enable=on,target=native -kernel "$image" </dev/null > "$tmp/$m.txt" 2>&1
  grep -qx done "$tmp/$m.txt" || { echo "target-cost.sh: $image failed:" >&2; tail -3 "$tmp/$m.txt" >&2; exit 1; }
done
python3 - "$tmp" "$methods" "$size" "$config" <<'PY'
import os, sys
tmp, methods, size, config = sys.argv[1], sys.argv[2].split(","), sys.argv[3], sys.argv[4]
cost = {}  # (scene, method) -> instructions per pixel written
divs = {}  # (scene, method) -> 64-bit division helper calls per pixel written
calls_of = {}  # (scene, method) -> 64-bit division helper calls in the draws
scenes = []
for m in methods:
    per_tick = None
    for line in open(os.path.join(tmp, m + ".txt")):
        f = line.split()
        if f[0] == "calibration":
            per_tick = int(f[1]) / int(f[2])
        elif f[0] == "cost":
            scene, ticks, written = f[1], int(f[2]), int(f[3])
            calls, wrapper = int(f[5]) + int(f[6]), int(f[7])
            if scene not in scenes:
                scenes.append(scene)
            instructions = ticks * per_tick - calls * wrapper
            cost[scene, m] = instructions / written if written else float("nan")
            divs[scene, m] = calls / written if written else float("nan")
            calls_of[scene, m] = calls
base = "gouraud" if "gouraud" in methods else None
print("Guest instructions per pixel written, Cortex-M3 (" + config + "), " + size +
      (" (in brackets: ratio to gouraud)" if base else ""))
print()
print("| scene | " + " | ".join(methods) + " |")
print("|---|" + "---:|" * len(methods))
for s in scenes:
    cells = []
    for m in methods:
        c = cost[s, m]
        cells.append("%.0f" % c + (" (%.2f)" % (c / cost[s, base]) if base and m != base else ""))
    print("| %s | %s |" % (s, " | ".join(cells)))
print()
calls_total = sum(calls_of[s, m] for s in scenes for m in methods)
if calls_total == 0:
    print("64-bit division helper calls (__aeabi_ldivmod + __aeabi_uldivmod), same run: none, for "
          "every method and scene (the firmware divides with fixedpoint/divide.hpp)")
else:
    print("64-bit division helper calls (__aeabi_ldivmod + __aeabi_uldivmod) per pixel written, "
          "same run")
    print()
    print("| scene | " + " | ".join(methods) + " |")
    print("|---|" + "---:|" * len(methods))
    for s in scenes:
        print("| %s | %s |" % (s, " | ".join("%.2f" % divs[s, m] for m in methods)))
PY
