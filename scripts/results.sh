#!/usr/bin/env bash
# Regenerates docs/RESULTS.md: builds the release preset's tinyphong-results and runs it over
# every paper scene (1 light, all methods) and the multi-light variants (2, 4, 8 lights).
# Usage: bash scripts/results.sh [--reps N] [--no-instructions]
#   --reps N: rounds per measurement (default 5; the machine and date go in the file).
#   The section on instructions per pixel written comes from scripts/instructions.sh
#   (callgrind, a few minutes); --no-instructions leaves it out. The last, the Cortex-M3 under
#   QEMU, from scripts/target-cost.sh --full (about 90 s; left out without qemu-system-arm or
#   the release tree's target images).
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
mkdir -p docs/charts
cpu=$(grep -m1 'model name' /proc/cpuinfo | cut -d: -f2 | sed 's/^ *//')
{
  cat <<EOF
# Results: every method on every paper scene

Error of every device method against the double-precision references (\`host/reference.hpp\`: Phong =
perspective-correct normals renormalised per pixel with true per-pixel L and V; angular = the
same with slerped normals), and frame time as a ratio to Gouraud's measured in the same run
(methods interleaved round-robin, median of $reps rounds; the frame time is the device's clear +
draw). Colour correctness is Vlasic's eq. 6.1, over pixels covered in both images; mean/max in
8-bit levels. A method is switched in before each of its timed frames, so the texture methods'
times include building their textures (docs/DECISIONS.md, "Vlasic's texture methods"). The
error figures are deterministic (integer device); the times are not: this
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

The flat, Gouraud, Phong, Duff, Bishop-Weimer, Brown and Vlasic rows (his texture methods also
on the multi-light scenes) are pinned in
\`tests/scenes/test_scene_accuracy.cpp\`; the
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
  python3 scripts/charts.py "$one" --drop-noskip --title "One light, six scenes" \
    --out-prefix docs/charts/one-light >&2
  cat <<EOF
### Run time against error (one light, the six scenes above)

Every method a point: the geometric mean of its time ratio to Gouraud over the six scenes (log
scale) against its mean colour correctness, and against its largest max |error|; the dashed line
joins the Pareto front (no method is both faster and better), the peer is the hollow square;
the verification variants (-noskip, the same image as their method) are left out. Drawn by
\`scripts/charts.py\` from the tables above.

![One light: colour correctness against time](charts/one-light-correctness.svg)

![One light: max error against time](charts/one-light-max-error.svg)

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
yardstick), exact fixed-point Phong, Duff, Bishop-Weimer (both forms), Brown, Vlasic's quadratic
shading and its subdivided-Gouraud comparison, his three texture methods (environment map, Blinn
map, quadratic Blinn map), the three Kuijk-Blake evaluations and kb-adaptive.

EOF
  many=$(mktemp)
  "$bin" --reps "$reps" --scenes "$multi" --methods gouraud,phong,duff,bishop-weimer,bishop-weimer-finite,brown,gouraud-subdivided,quadratic,envmap,blinn-map,quadratic-blinn-map,kb,kb-decomposition,kb-exact,kb-adaptive --peer llvmpipe | tail -n +3 | tee "$many"
  python3 scripts/charts.py "$many" --title "2, 4 and 8 lights, eighteen scenes" \
    --out-prefix docs/charts/many-lights >&2
  rm -f "$many"
  cat <<EOF

### Run time against error (2, 4 and 8 lights)

As for one light, over the eighteen multi-light scenes above.

![2, 4 and 8 lights: colour correctness against time](charts/many-lights-correctness.svg)

![2, 4 and 8 lights: max error against time](charts/many-lights-max-error.svg)
EOF
  cat <<EOF

## Bishop & Weimer's own table, beside ours

Bishop & Weimer (1986) timed their methods on a microVAX-II, 14,620 polygons at 2048 x 2048:
Gouraud 406 s, their Taylor expansion with light and eye at infinity 767 s (1.89x Gouraud),
with a finite eye 850 s (2.09x), Duff's method 2,597 s (6.4x, of which 1,420 s in the square
root), Phong 3,900 s (9.6x). Ours at the same size, on the teapot (4,032 triangles) and
sphere-512: the wall-time ratio to Gouraud measured in one run (median of $reps rounds) and the
ratio of instructions per pixel written (callgrind, as in the last section). The teapot is seen
in perspective (a finite eye), sphere-512 orthographically with a point light: on both, the
finite form's H (and on the sphere its L) varies over each triangle.

EOF
  bw=$(mktemp)
  "$bin" --reps "$reps" --scenes teapot,sphere-512 --size 2048x2048 \
    --methods gouraud,bishop-weimer,bishop-weimer-finite,duff,phong > "$bw"
  ins=$(mktemp)
  bash scripts/instructions.sh --scenes teapot,sphere-512 --size 2048x2048 \
    --methods gouraud,bishop-weimer,bishop-weimer-finite,duff,phong > "$ins"
  python3 - "$bw" "$ins" <<'PYEOF'
import sys
times, instr = {}, {}
scene = None
for line in open(sys.argv[1]):
    if line.startswith('### '):
        scene = line.split()[1]
    cells = [c.strip() for c in line.strip().strip('|').split('|')]
    if scene and len(cells) == 8 and cells[0] in ('gouraud', 'bishop-weimer', 'bishop-weimer-finite', 'duff', 'phong'):
        times[scene, cells[0]] = float(cells[7])
methods = []
for line in open(sys.argv[2]):
    cells = [c.strip() for c in line.strip().strip('|').split('|')]
    if cells[0] == 'scene':
        methods = cells[1:]
    elif methods and cells[0] in ('teapot', 'sphere-512'):
        for m, v in zip(methods, cells[1:]):
            instr[cells[0], m] = float(v)
paper = [('gouraud', 'Gouraud', 406, 1.00), ('bishop-weimer', 'Taylor, light and eye at infinity', 767, 1.89),
         ('bishop-weimer-finite', 'Taylor, finite eye', 850, 2.09),
         ('duff', 'Duff', 2597, 6.40), ('phong', 'Phong', 3900, 9.61)]
print('| method | paper: s | paper: / Gouraud | teapot: time / Gouraud | teapot: instructions / Gouraud | sphere-512: time / Gouraud | sphere-512: instructions / Gouraud |')
print('|---|---:|---:|---:|---:|---:|---:|')
for m, name, s, r in paper:
    row = [f'{name} (`{m}`)', f'{s:,}', f'{r:.2f}']
    for sc in ('teapot', 'sphere-512'):
        row.append(f"{times[sc, m]:.2f}")
        row.append(f"{instr[sc, m] / instr[sc, 'gouraud']:.2f} ({instr[sc, m]:.0f}/px)")
    print('| ' + ' | '.join(row) + ' |')
def span(values, digits=2):
    lo, hi = f'{min(values):.{digits}f}', f'{max(values):.{digits}f}'
    return lo if lo == hi else f'{lo} to {hi}'
scenes = ('teapot', 'sphere-512')
ratio = lambda table, a, b: [table[sc, a] / table[sc, b] for sc in scenes]
print()
print(f"""How ours compare: the order is theirs, the Taylor expansion below Duff and Duff below Phong.
The finite-eye form costs {span(ratio(times, 'bishop-weimer-finite', 'bishop-weimer'))} times the
expansion with everything at infinity in time and
{span(ratio(instr, 'bishop-weimer-finite', 'bishop-weimer'))} in instructions (theirs 1.11): its
pixel loop is the same, its set-up takes the halfway vector (and a point light's L) at three
vertices instead of one centroid and expands a quotient of two varying vectors, which weighs
more where triangles are small.
Phong costs {span(ratio(times, 'phong', 'duff'))} times Duff in time here and
{span(ratio(instr, 'phong', 'duff'))} in instructions (theirs 1.50); Duff costs
{span(ratio(times, 'duff', 'bishop-weimer'))} times the Taylor expansion in time and
{span(ratio(instr, 'duff', 'bishop-weimer'))} in instructions (theirs 3.39). The ratios to Gouraud
are larger than theirs because our Gouraud is an integer loop of a few instructions per pixel
({span([instr[sc, 'gouraud'] for sc in scenes], 0)} per pixel written, the vertex work included),
where theirs ran the same floating-point testbed as the other methods; because our Taylor
expansion keeps one polynomial per colour channel in 64-bit fixed point (three times the
paper's one intensity, and a multiply per channel after the specular lookup), which costs more
than the paper's "5 additions and 1 memory access"; and because Duff's square root and division,
1,420 of its 2,597 s in the paper, are a smaller share of its cost here (an integer root from a
seed and two Newton steps, and one 64-bit division per pixel, beside 64-bit products per
light), so Duff gains less over the expansion. At 2048 x 2048 a drawn teapot triangle covers
about 800 pixels, more than the paper's 14,620 polygons (at most about 290 each, had they
filled the frame): per-triangle set-up weighs less here than there.""")
PYEOF
  rm -f "$bw" "$ins"
  cat <<EOF

## Brown's convex-hull culling

Brown culls a light from a triangle when all six control points of its Bézier triangle of N·H
lie below the smoothstep's lower end c_lo: no pixel of it can then have a highlight. He reports
that this left 10 % of the pixels of his scene (a space shuttle at 1024 x 1024; his examples'
highlights end at 1.8° to 3°) to evaluate. Ours, on every paper scene at its own size, from the device's
counters (\`tinyphong render SCENE -m brown\`): the (pixel, light) pairs that evaluated a
highlight, as a share of all, and the (triangle, light) pairs culled. The material's n = 20
gives c_lo = 0.890 (a highlight out to 27°, nine times the widest of his), which is why more remains
here; the triangle scene's one large triangle is never culled.

| scene | lights | pixels shaded | highlights evaluated (pixel, light) | share | (triangle, light) culled |
|---|---:|---:|---:|---:|---:|
EOF
  python3 - "$(pwd)" <<'PYEOF'
import glob, json, os, subprocess, sys, tempfile
root = sys.argv[1]
png = os.path.join(tempfile.mkdtemp(), 'brown.png')
for path in sorted(glob.glob(os.path.join(root, 'scenes', '*.json'))):
    name = os.path.basename(path)[:-5]
    lights = len(json.load(open(path))['lights'])
    out = subprocess.run([os.path.join(root, 'build/release/host/tinyphong'), 'render', path, '-m',
                          'brown', '-o', png], capture_output=True, text=True, check=True).stdout
    c = {}
    for line in out.splitlines():
        parts = line.split('=')
        if len(parts) == 2:
            c[parts[0].strip()] = int(parts[1])
    shaded, spec = c['pixels_shaded'], c['specular_evaluations']
    share = spec / (shaded * lights)
    print(f"| {name} | {lights} | {shaded:,} | {spec:,} | {100 * share:.1f} % | {c['lights_skipped_triangle']:,} |")
os.remove(png)
PYEOF
  echo
  bash scripts/vlasic-table.sh
  if [ "$instructions" = 1 ]; then
    cat <<EOF

## Instructions per pixel written

The steadier cost figure: instructions executed inside \`tp::fw::Device::draw\` (all of it: the
vertex cache, clipping, set-up, spans and pixels; the clear is outside), counted by
callgrind for one frame of each scene, divided by the frame's pixels written (repeatable to the
instruction on any x86-64 machine with the same compiler):

    bash scripts/instructions.sh --methods flat,gouraud,phong,duff,bishop-weimer,bishop-weimer-finite,brown,gouraud-subdivided,quadratic,envmap,blinn-map,quadratic-blinn-map,kb,kb-adaptive

Measured $(date +%Y-%m-%d) on the machine above.

EOF
    bash scripts/instructions.sh --methods flat,gouraud,phong,duff,bishop-weimer,bishop-weimer-finite,brown,gouraud-subdivided,quadratic,envmap,blinn-map,quadratic-blinn-map,kb,kb-adaptive
  fi
  if command -v qemu-system-arm >/dev/null && [ -d build/release/target ]; then
    cat <<EOF

## On a Cortex-M3 (QEMU)

The device's firmware cross-compiled for the Cortex-M3 (-O2) and run under
\`qemu-system-arm -M mps2-an385 -icount shift=0\`, which counts guest instructions: every method
on every scene at the scenes' own resolutions, with the ratio to Gouraud, and the calls of the
64-bit division helpers (counted; none since the firmware divides with fixedpoint/divide.hpp).
docs/TARGET.md explains the measurement and gives the same at 160x120.

    bash scripts/target-cost.sh --full

Measured $(date +%Y-%m-%d); guest instruction counts are the same on any host.

EOF
    bash scripts/target-cost.sh --full
  fi
} > "$out.tmp"
mv "$out.tmp" "$out"
echo "wrote $out"
