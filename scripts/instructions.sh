#!/usr/bin/env bash
# Instructions per pixel written of the device's draw, for every method and paper scene (a
# benchmark, not a test): callgrind counts the instructions executed inside
# tp::fw::Device::draw(const DrawCmd&) while the release CLI renders the scene once; the count is
# divided by the frame's pixels_written counter. Instruction counts are repeatable on a shared
# machine. The toggle names the one top-level function exactly: callgrind toggles collection on
# every entry to a matching function, so the pattern 'tp::fw::Device::draw*' switched it off
# again inside draw_triangle (called from draw) and left out its work — the vertex normals,
# the clip test, the projection — until 2026-12-03 (docs/DECISIONS.md, "The vertex cache
# projects").
# It runs tinyphong-draw (bench/draw.cpp): the same DeviceRenderer::render as `tinyphong render`,
# without the image library, whose dependency libhwy executes rdtscp at load time — an
# instruction valgrind refuses on processors that do not advertise it.
#
# Usage: bash scripts/instructions.sh [--scenes a,b,...] [--methods m1,m2,...] [--budget B]
#                                    [--size WxH] [--markdown]
#   defaults: every paper scene and its -l2/-l4/-l8 variants (scenes/*.json), and the methods
#   gouraud, phong, kb, kb-adaptive. Prints one table row per scene (methods as columns).
#   --budget B: kb-adaptive's error budget in output levels (default: each scene's, else 1).
#   --size WxH: render at this resolution instead of each scene's own.
set -euo pipefail
cd "$(dirname "$0")/.."
scenes=""
methods="gouraud,phong,kb,kb-adaptive"
budget=()
size=()
while [ $# -gt 0 ]; do
  case "$1" in
    --scenes) scenes=$2; shift 2 ;;
    --methods) methods=$2; shift 2 ;;
    --budget) budget=(--budget "$2"); shift 2 ;;
    --size) size=(--size "$2"); shift 2 ;;
    --markdown) shift ;;  # the only format; kept for symmetry with scripts/results.sh
    *) echo "usage: $0 [--scenes a,b] [--methods m1,m2] [--budget B] [--size WxH]" >&2; exit 2 ;;
  esac
done
command -v valgrind >/dev/null || { echo "instructions.sh: valgrind is needed (apt-get install valgrind)" >&2; exit 1; }
cmake --preset release >/dev/null
cmake --build --preset release -j "$(nproc)" --target tinyphong-draw >/dev/null
bin=build/release/bench/tinyphong-draw
if [ -z "$scenes" ]; then
  scenes=$(for f in scenes/*.json scenes/stress/*.json; do [ -f "$f" ] && echo "${f#scenes/}"; done | sed 's/\.json$//' | paste -sd, -)
fi
tmp=$(mktemp -d)
trap 'rm -rf "$tmp"' EXIT
header="| scene |"
rule="|---|"
for m in ${methods//,/ }; do header+=" $m |"; rule+="---|"; done
echo "$header"
echo "$rule"
for s in ${scenes//,/ }; do
  row="| $s |"
  for m in ${methods//,/ }; do
    out="$tmp/cg.out"
    log=$(valgrind --tool=callgrind --toggle-collect='tp::fw::Device::draw(tp::fw::DrawCmd const&)' \
      --callgrind-out-file="$out" "$bin" "scenes/$s.json" --method "$m" "${budget[@]}" "${size[@]}" 2>/dev/null)
    px=$(echo "$log" | awk '$1 == "pixels_written" {print $3}')
    ir=$(awk '/^summary:/ {print $2}' "$out")
    if [ -z "$px" ] || [ "$px" = 0 ] || [ -z "$ir" ]; then row+=" — |"; continue; fi
    row+=" $(( (ir + px / 2) / px )) |"
  done
  echo "$row"
done
