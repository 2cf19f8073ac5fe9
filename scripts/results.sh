#!/usr/bin/env bash
# Regenerates docs/RESULTS.md: builds the release preset's tinyphong-results and runs it over
# every paper scene (1 light, all methods) and the multi-light variants (2, 4, 8 lights).
# Usage: bash scripts/results.sh [--reps N]   (default 5; the machine and date go in the file)
set -euo pipefail
cd "$(dirname "$0")/.."
reps=5
[ "${1:-}" = "--reps" ] && reps=$2
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

Regenerate: \`bash scripts/results.sh --reps $reps\` (it runs
\`build/release/bench/tinyphong-results --reps $reps [--scenes ...] [--methods ...]\`).
Machine: $(nproc) cores, ${cpu:-unknown CPU}, $(g++ --version | head -1), -O2.

The flat, Gouraud and Phong rows are pinned in \`tests/scenes/test_scene_accuracy.cpp\`; the
Kuijk-Blake rows in \`tests/kb/test_kb_device.cpp\`; kb-adaptive is checked against kb and
its own exact evaluation (\`kb-adaptive-exact\`) on every scene in
\`tests/kb/test_kb_adaptive_scenes.cpp\`. docs/KUIJK-BLAKE.md discusses the Kuijk-Blake columns,
their setup share, kb-adaptive and the speed targets; instructions per pixel (a steadier cost
figure than these times) are in docs/KUIJK-BLAKE.md ("kb-adaptive"), from
\`bash scripts/instructions.sh\`.

## One light, all methods

EOF
  one=$(mktemp)
  "$bin" --reps "$reps" --scenes "$base" | tee "$one"
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
yardstick), exact fixed-point Phong, the three Kuijk-Blake evaluations and kb-adaptive.

EOF
  "$bin" --reps "$reps" --scenes "$multi" --methods gouraud,phong,kb,kb-decomposition,kb-exact,kb-adaptive | tail -n +3
} > "$out.tmp"
mv "$out.tmp" "$out"
echo "wrote $out"
