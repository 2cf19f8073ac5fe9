#!/usr/bin/env bash
# Regenerates docs/RESULTS.md: builds the release preset's tinyphong-results and runs it over
# every paper scene (1 light, all methods) and the multi-light variants (2, 4, 8 lights).
# Usage: bash scripts/results.sh [--reps N] [--no-instructions]
#   --reps N: rounds per measurement (default 5; the machine and date go in the file).
#   The last section, instructions per pixel written, comes from scripts/instructions.sh
#   (callgrind, a few minutes); --no-instructions leaves it out.
set -euo pipefail
cd "$(dirname "$0")/.."
reps=5
instructions=1
while [ $# -gt 0 ]; do
  case "$1" in
    --reps) reps=$2; shift 2 ;;
    --no-instructions) instructions=0; shift ;;
    *) echo "usage: $0 [--reps N] [--no-instructions]" >&2; exit 2 ;;
  esac
done
cmake --preset release >/dev/null
cmake --build --preset release -j "$(nproc)" --target tinyphong-results >/dev/null
bin=build/release/bench/tinyphong-results
base="sphere-32,sphere-40,sphere-512,dodecahedron-30,triangle,teapot"
multi=""
for l in 2 4 8; do
  for s in ${base//,/ }; do multi+="${multi:+,}$s-l$l"; done
done
out=docs/RESULTS.md
cpu=$(grep -m1 'model name' /proc/cpuinfo | cut -d: -f2 | sed 's/^ *//')
{
  cat <<EOF
# Results: every method on every paper scene

Error of every device method against the double-precision references (\`host/reference.hpp\`: Phong =
perspective-correct normals renormalised per pixel with true per-pixel L and V; angular = the
same with slerped normals), and frame time as a ratio to Gouraud's measured in the same run
(methods interleaved round-robin, median of $reps rounds; the frame time is the device's clear +
draw). Colour correctness is Vlasic's eq. 6.1, over pixels covered in both images; mean/max in
8-bit levels. The error figures are deterministic (integer device); the times are not: this
machine is shared, single ratios move by up to ±30 % between runs.

The \`llvmpipe\` rows are the peer a desktop user would pick instead of the device: Mesa's
llvmpipe through OSMesa (Debian's libosmesa6-dev), one thread (\`LP_NUM_THREADS=0\`), per-pixel
float Blinn-Phong in GLSL with the reference's formula (\`host/llvmpipe.hpp\`), timed in the same
rounds (clear + draws + glFinish) and compared with the references like every method.
\`tests/scenes/test_llvmpipe_peer.cpp\` checks it against the double reference on the sphere and
triangle scenes: within 1 level wherever both cover a pixel, coverage differing only on
silhouette pixels.

Regenerate: \`bash scripts/results.sh --reps $reps\` (it runs
\`build/release/bench/tinyphong-results --reps $reps [--scenes ...] [--methods ...] --peer
llvmpipe\`).
Machine: $(nproc) cores, ${cpu:-unknown CPU}, $(g++ --version | head -1), -O2.

The flat, Gouraud and Phong rows are pinned in \`tests/scenes/test_scene_accuracy.cpp\`; the
Kuijk-Blake rows in \`tests/kb/test_kb_device.cpp\`; kb-adaptive is checked against kb and
its own exact evaluation (\`kb-adaptive-exact\`) on every scene in
\`tests/kb/test_kb_adaptive_scenes.cpp\`. docs/KUIJK-BLAKE.md discusses the Kuijk-Blake columns,
their setup share, kb-adaptive and the speed targets; instructions per pixel (a steadier cost
figure than these times) are in the last section, from \`bash scripts/instructions.sh\`
(kb-adaptive's history of them in docs/KUIJK-BLAKE.md).

## One light, all methods

EOF
  one=$(mktemp)
  "$bin" --reps "$reps" --scenes "$base" --peer llvmpipe | tee "$one"
  cat <<EOF
### Run time against error (one light, the six scenes above)

Geometric mean of the time ratio to Gouraud; mean and worst colour correctness (Phong reference).

| method | time / Gouraud (geometric mean) | colour correctness: mean | worst |
|---|---|---|---|
EOF
  awk -F'|' '/^\| [a-z]/ && $2 !~ /method/ {
      m = $2; gsub(/ /, "", m); cc = $3 + 0; t = $9 + 0
      if (!(m in n)) order[++k] = m
      n[m]++; lt[m] += log(t); sc[m] += cc; if (!(m in w) || cc < w[m]) w[m] = cc }
    END { for (i = 1; i <= k; i++) { m = order[i]
      printf "| %s | %.2f | %.4f | %.4f |\n", m, exp(lt[m] / n[m]), sc[m] / n[m], w[m] } }' "$one"
  rm -f "$one"
  cat <<EOF

## 2, 4 and 8 lights

Lights as listed in \`scenes/README.md\` (the base light first). Methods: Gouraud (the
yardstick), exact fixed-point Phong, Duff, the three Kuijk-Blake evaluations and kb-adaptive.

EOF
  "$bin" --reps "$reps" --scenes "$multi" --methods gouraud,phong,duff,kb,kb-decomposition,kb-exact,kb-adaptive --peer llvmpipe | tail -n +3
  if [ "$instructions" = 1 ]; then
    cat <<EOF

## Instructions per pixel written

The steadier cost figure: instructions executed inside \`tp::fw::Device::draw\` (all of it: the
vertex cache, clipping, set-up, spans and pixels; the clear is outside), counted by
callgrind for one frame of each scene, divided by the frame's pixels written (repeatable to the
instruction on any x86-64 machine with the same compiler). \`bash scripts/instructions.sh
--methods flat,gouraud,phong,duff,kb,kb-adaptive\`, $(date +%Y-%m-%d).

EOF
    bash scripts/instructions.sh --methods flat,gouraud,phong,duff,kb,kb-adaptive
  fi
} > "$out.tmp"
mv "$out.tmp" "$out"
echo "wrote $out"
