#!/usr/bin/env bash
# The CLI's own options on bad values: --size must be two whole numbers in 1..4096 joined by x
# (sscanf's %d wrapped 4294967297 to 1 and ignored trailing text), --rotate a finite angle
# within ±1e6 degrees (NaN, infinity and 1e308, whose radians overflow, drew a black image and
# exited 0). Each refusal exits non-zero, names the option and writes no image; good values work.
# A frame the device refuses at the rotation asked for is refused by render, record and reference.
# And the exit statuses: 2 on a bad option of any subcommand, 3 when stress cannot write its file;
# stress --list lists what --quick and --cases select; --budget for a method that reads none is noted.
# Usage: cli_options_test.sh TINYPHONG SCENES_DIR
set -euo pipefail
tp=$1 scenes=$2
work=$(mktemp -d)
trap 'rm -rf "$work"' EXIT
fail=0

# refused TEXT ARGS...: the command must exit non-zero, print TEXT and write no image.
refused() {
  local text=$1 out status=0
  shift
  rm -f "$work/out.png"
  out=$("$tp" "$@" -o "$work/out.png" 2>&1) || status=$?
  if [ "$status" -eq 0 ] || ! grep -qF -- "$text" <<<"$out" || [ -e "$work/out.png" ]; then
    echo "FAIL: $* : status $status, output '$out'"; fail=1
  else
    echo "ok: $*"
  fi
}

tri=$scenes/triangle.json
for size in 4294967297x5 4294967808x4294967808 10x20junk 0x10 4097x10 10x -5x5 x 10x+5 " 10x10"; do
  refused "--size: expected WIDTHxHEIGHT, each 1..4096, got '$size'" render "$tri" --size "$size"
done
# Decimal only: CLI11's own reading took hexadecimal and a leading space (found by review,
# 2026-12-07), text --seed refuses.
for angle in nan -nan inf -inf 1e308 1000001 0x10 0x1p4 " 16" "16 " +-5 ++5 + ""; do
  refused "--rotate: an angle in degrees, finite and within ±1e6, got '$angle'" \
    reference "$tri" --rotate "$angle"
  refused "--rotate: an angle in degrees" render "$tri" --rotate "$angle"
  refused "--rotate: an angle in degrees" record "$tri" --rotate "$angle"
done

"$tp" render "$tri" --size 4096x16 --rotate -1e6 -o "$work/ok.png" >/dev/null ||
  { echo "FAIL: --size 4096x16 --rotate -1e6 refused"; fail=1; }
"$tp" render "$tri" --size 16X8 --rotate 30.5 -o "$work/ok.png" >/dev/null ||
  { echo "FAIL: --size 16X8 --rotate 30.5 refused"; fail=1; }
for angle in +45 -12.5 1e3 .5; do
  "$tp" render "$tri" --size 16x8 --rotate "$angle" -o "$work/ok.png" >/dev/null ||
    { echo "FAIL: --rotate $angle refused"; fail=1; }
done

# A scene is checked unturned; turned 45 degrees this slab's corners (2.5 × 10,000 units from the
# axis on x and z) reach 35,355 in eye space, beyond the device's Q15.16. render named no file,
# record wrote a stream that replay then refused, and reference drew it (found by review,
# 2026-12-07). Each now refuses the frame, naming the scene and the rotation, and writes nothing.
printf 'v 2.5 0 2.5\nv 2.5 0.5 2.5\nv -2.5 0 2.5\nv 2.5 0 -2.5\nf 1 2 3\nf 1 4 2\n' > "$work/slab.obj"
cat > "$work/slab.json" <<'JSON'
{"camera": {"type": "orthographic", "extents": [-10000, 10000, -10000, 10000],
            "near": -10000, "far": 10000},
 "lights": [{"type": "directional", "direction": [0, 0, 1]}],
 "material": {"colour": [1, 1, 1], "ka": 0.1, "kd": 0.6, "ks": 0.3, "n": 20},
 "meshes": [{"obj": "slab.obj", "transform": {"scale": 10000}}], "cull": false}
JSON
for cmd in render record reference; do
  refused "slab.json: the device refused the frame at rotation 45 degrees: command draw at word" \
    $cmd "$work/slab.json" --size 64x64 --rotate 45
done
"$tp" render "$work/slab.json" --size 64x64 -o "$work/ok.png" >/dev/null ||
  { echo "FAIL: the slab unturned refused"; fail=1; }
# A model-view entry beyond the device's 2^14 at one rotation: 10,000 units out on x, seen from
# 10,000 units away on z, is 20,000 deep turned 90 degrees. Named with the rotation, as the host
# checks it before the device would.
printf 'v 0 1 0\nv 1 0 0\nv 0 0 1\nf 1 2 3\n' > "$work/tri.obj"
cat > "$work/orbit.json" <<'JSON'
{"camera": {"type": "perspective", "position": [0, 0, 10000], "target": [0, 0, 0], "fov_y": 60,
            "near": 1, "far": 10000},
 "lights": [{"type": "directional", "direction": [0, 0, 1]}],
 "meshes": [{"obj": "tri.obj", "transform": {"translate": [10000, 0, 0]}}], "cull": false}
JSON
refused "orbit.json: the model-view at rotation 90 degrees does not fit the device: model-view[3][2]" \
  render "$work/orbit.json" --size 64x48 --rotate 90
"$tp" render "$work/orbit.json" --size 64x48 -o "$work/ok.png" >/dev/null ||
  { echo "FAIL: the orbit unturned refused"; fail=1; }

# Two meshes that each render alone render together. The driver keeps every mesh's vertices in
# one buffer, and a draw was refused for a vertex of another mesh that its own model-view would
# take out of range: here the quad's corners (10,000 units, scaled down in its transform) under
# the sphere's scale of 4 (found by review, 2026-12-08).
cat > "$work/two.json" <<'JSON'
{"camera": {"type": "orthographic", "extents": [-6, 6, -6, 6], "near": -10, "far": 10},
 "lights": [{"type": "point", "position": [1.8, 2.2, 2.8]}],
 "material": {"colour": [0.2, 0.4, 1], "ka": 0.1, "kd": 0.6, "ks": 0.4, "n": 20},
 "meshes": [{"generator": "quad", "params": {"half_size": 10000},
             "transform": {"scale": 0.0004, "translate": [-2, 0, 0]}},
            {"generator": "octa-sphere", "params": {"subdivisions": 1},
             "transform": {"scale": 4, "translate": [2, 0, 0]}}]}
JSON
out=$("$tp" render "$work/two.json" --size 64x64 --compare -o "$work/two.png" 2>&1) &&
  grep -qE "^pixels compared: +[1-9]" <<<"$out" &&
  grep -qE "^only in first: +0$" <<<"$out" && grep -qE "^only in second: +0$" <<<"$out" ||
  { echo "FAIL: two meshes, each fine alone, together: '$out'"; fail=1; }

# exits STATUS TEXT ARGS...: the command must exit with STATUS and print TEXT (found by review,
# 2026-12-06: CLI11's own codes came through, 104 to 114, and stress took -1, 2^64, "" and 0x10
# as seeds; a JSON file lost to a full disk exited 0).
exits() {
  local want=$1 text=$2 out status=0
  shift 2
  out=$("$tp" "$@" 2>&1 >/dev/null) || status=$?
  if [ "$status" -ne "$want" ] || ! grep -qF -- "$text" <<<"$out"; then
    echo "FAIL: $* : status $status (want $want), output '$out'"; fail=1
  else
    echo "ok: $*"
  fi
}
for seed in -1 18446744073709551616 "" 0x10 12x; do
  exits 2 "--seed: a whole number in 0..18446744073709551615, got '$seed'" \
    stress --cases ab-min --methods flat --seed "$seed"
done
exits 2 "bogus" stress --bogus
exits 2 "--method: unknown shading method 'bogus'" render "$tri" --method bogus -o "$work/out.png"
exits 2 "--method: unknown shading method 'bogus'" record "$tri" --method bogus -o "$work/out.tpcmd"
exits 2 "--size" render "$tri" --size 0x5 -o "$work/out.png"
exits 2 "--size: expected WIDTHxHEIGHT" record "$tri" --size 5x0 -o "$work/out.tpcmd"
exits 2 "--methods: unknown shading method 'bogus'" stress --cases ab-min --methods flat,bogus
# A list naming no method is refused as that, not by taking the next option for a method
# (CLI11's delimited list did: "unknown shading method '--cases'").
exits 2 "--methods: no method named in ','" stress --methods , --cases ab-min
exits 3 "/dev/full: cannot write" stress --cases ab-min --methods flat --json /dev/full
# Standard output that cannot be written is an error, exit 1 (3 for stress, whose 1 is a result
# out of bounds): a report redirected to a full disk was lost with exit 0 (found by review,
# 2026-12-07). And compare's --worst names its range in whole numbers.
for cmd in methods "stress --cases ab-min --methods flat" "memory"; do
  want=1
  [ "${cmd%% *}" = stress ] && want=3
  status=0
  out=$("$tp" $cmd 2>&1 >/dev/full) || status=$?
  if [ "$status" != "$want" ] || ! grep -qF "tinyphong: standard output: cannot write" <<<"$out"; then
    echo "FAIL: $cmd > /dev/full: status $status (want $want), '$out'"; fail=1
  else
    echo "ok: $cmd > /dev/full: status $status"
  fi
done
exits 2 "--worst: a whole number in 0..2147483647, got '-1'" compare "$work/ok.png" "$work/ok.png" --worst -1
# Whole-number options read decimal digits only, as --rotate and --seed do: CLI11 took
# hexadecimal and a leading space, and called 1e3, 1.5 and nan out of range (found by review,
# 2026-12-08).
for v in 0x3 " 3" 1e3 1.5 nan +-3 ""; do
  exits 2 "--budget: a whole number in 1..16 (decimal digits), got '$v'" \
    render "$tri" -m kb-adaptive --budget "$v" -o "$work/out.png"
  exits 2 "--worst: a whole number in 0..2147483647 (decimal digits), got '$v'" \
    compare "$work/ok.png" "$work/ok.png" --worst "$v"
  exits 2 "--row: a whole number in 0..2147483647 (decimal digits), got '$v'" \
    compare "$work/ok.png" "$work/ok.png" --row "$v"
  exits 2 "--vertices: a whole number in 0..16777216 (decimal digits), got '$v'" memory --vertices "$v"
done
exits 2 "--budget: a whole number in 1..16, got '17'" record "$tri" --budget 17 -o "$work/o.tpcmd"
exits 2 "--indices: a whole number in 0..67108864, got '99999999999999999999'" \
  memory --indices 99999999999999999999
# Read as written: CLI11's own conversion took a leading 0 for octal ("010" was 8, "08" refused).
"$tp" memory --vertices 010 | grep -q "^Device memory block in bytes (Device::memory_required), 10 vertices" &&
  "$tp" memory --vertices 08 | grep -q ", 8 vertices" ||
  { echo "FAIL: memory --vertices 010 / 08 not read as decimal"; fail=1; }
"$tp" render "$tri" -m kb-adaptive --size 32x16 --budget +3 -o "$work/b3p.png" >/dev/null &&
  "$tp" render "$tri" -m kb-adaptive --size 32x16 --budget 3 -o "$work/b3.png" >/dev/null &&
  cmp -s "$work/b3p.png" "$work/b3.png" || { echo "FAIL: --budget +3 is not --budget 3"; fail=1; }
# One file for --json and --pin-bounds kept the bounds rows alone; rows pinned at another seed
# are not the bounds the table defines (found by review, 2026-12-08): refused, nothing run.
exits 2 "are one file: nothing run" \
  stress --cases ab-min --methods flat --json "$work/same.out" --pin-bounds "$work/./same.out"
exits 2 "--pin-bounds pins the default seed's bounds (20261202" \
  stress --cases ab-min --methods flat --seed 1 --pin-bounds "$work/pin.out"
[ ! -e "$work/same.out" ] && [ ! -e "$work/pin.out" ] ||
  { echo "FAIL: a refused stress run wrote a file"; fail=1; }
# A method named twice runs once (it ran twice, every row doubled; found by review, 2026-12-07).
twice=$("$tp" stress --cases ab-min --methods flat,flat 2>&1 || true)
grep -q "^1 result, " <<<"$twice" || { echo "FAIL: stress --methods flat,flat: '$twice'"; fail=1; }
# (its verdict is not the point: the bounds are the default seed's, docs/STABILITY.md)
"$tp" stress --cases ab-min --methods flat --seed 18446744073709551615 --json "$work/s.json" \
  >/dev/null 2>&1 || true
grep -q '"seed": 18446744073709551615' "$work/s.json" ||
  { echo "FAIL: the largest seed was not the one used"; fail=1; }

# --list lists the cases --quick and --cases select, and a filter matching only cases outside the
# quick subset says so (--list ignored both and listed all 36; "no case matches --cases
# 'grazing-0.1'" although the case exists; found by review, 2026-12-07).
listed=$("$tp" stress --list --cases grazing)
all=$("$tp" stress --list | wc -l)
quick=$("$tp" stress --list --quick | wc -l)
if [ -z "$listed" ] || grep -qv "^[^[:space:]]*grazing" <<<"$listed" || [ "$quick" -ge "$all" ] ||
   [ "$quick" -ne "$("$tp" stress --list | grep -c "	quick	")" ]; then
  echo "FAIL: stress --list with --cases / --quick: '$listed', $quick of $all"; fail=1
else
  echo "ok: stress --list lists the selected cases ($quick quick of $all)"
fi
exits 2 "no quick case matches --cases 'grazing-0.1' (1 case outside the quick subset does: leave out --quick)" \
  stress --quick --cases grazing-0.1
exits 2 "no case matches --cases 'nosuchcase' (tinyphong stress --list names the cases)" \
  stress --list --cases nosuchcase
# --budget for a method that reads none: drawn, and the user told (it was taken without a word;
# found by review, 2026-12-07); for kb-adaptive no note. The image is the one without --budget.
out=$("$tp" render "$tri" -m kb --budget 4 -o "$work/b4.png" 2>&1 >/dev/null) &&
  "$tp" render "$tri" -m kb -o "$work/b1.png" >/dev/null &&
  cmp -s "$work/b4.png" "$work/b1.png" &&
  grep -qF "note: --budget 4 has no effect on $tri: its method kb reads no error budget (kb-adaptive, kb-adaptive-noskip do)" <<<"$out" ||
  { echo "FAIL: render -m kb --budget 4: '$out'"; fail=1; }
out=$("$tp" record "$tri" -m gouraud --budget 2 -o "$work/b.tpcmd" 2>&1 >/dev/null) &&
  grep -qF "note: --budget 2 has no effect" <<<"$out" ||
  { echo "FAIL: record -m gouraud --budget 2: '$out'"; fail=1; }
out=$("$tp" render "$tri" -m kb-adaptive --budget 4 -o "$work/b4.png" 2>&1 >/dev/null) &&
  ! grep -q "note:" <<<"$out" || { echo "FAIL: render -m kb-adaptive --budget 4: '$out'"; fail=1; }

# compare (found by review, 2026-12-08). With no pixel covered in both images it printed a
# perfect score (correctness 1, PSNR inf); now it says there is nothing to measure.
out=$("$tp" render "$tri" --rotate 180 --size 16x16 --compare -o "$work/none.png")
grep -qF "no pixel is covered in both images: no error to measure" <<<"$out" &&
  ! grep -q "colour correctness\|PSNR" <<<"$out" || { echo "FAIL: nothing covered: '$out'"; fail=1; }
# A scene's background other than black: compare took every pixel for covered. --background gives
# it, and compare then prints render --compare's figures; without it, compare says why every pixel
# counts.
sed 's/"background": \[[^]]*\]/"background": [0.2, 0.2, 0.2]/' "$tri" > "$work/grey.json"
grep -q '"background": \[0.2, 0.2, 0.2\]' "$work/grey.json" || { echo "FAIL: no grey scene"; fail=1; }
figures() { grep -E "^(pixels compared|only in|colour correctness|PSNR|mean|max)" <<<"$1"; }
rendered=$("$tp" render "$work/grey.json" --size 64x64 -m gouraud --compare -o "$work/grey.png")
"$tp" reference "$work/grey.json" --size 64x64 -o "$work/grey-ref.png" >/dev/null
given=$("$tp" compare "$work/grey-ref.png" "$work/grey.png" --background 51,51,51 2>"$work/err")
[ -n "$(figures "$rendered")" ] && [ "$(figures "$rendered")" = "$(figures "$given")" ] &&
  [ ! -s "$work/err" ] || { echo "FAIL: compare --background: '$given' vs '$rendered'"; fail=1; }
"$tp" compare "$work/grey-ref.png" "$work/grey.png" >/dev/null 2>"$work/err"
grep -qF "note: no pixel of either image is the background colour 0,0,0" "$work/err" ||
  { echo "FAIL: compare of a grey scene without --background: '$(cat "$work/err")'"; fail=1; }
for bg in 51,51 1,2,3,4 256,0,0 0x1,0,0 ,,; do
  exits 2 "--background: R,G,B: three whole numbers in 0..255, got '$bg'" \
    compare "$work/grey-ref.png" "$work/grey.png" --background "$bg"
done
# A float image was read as 8-bit, NaN as 0 (the background): refused, naming the file.
"$tp" reference "$tri" --size 8x8 -o "$work/r8.png" --exr "$work/r8.exr" >/dev/null
exits 1 "cannot read $work/r8.exr: its pixels are float, not uint8" \
  compare "$work/r8.exr" "$work/r8.png"

[ $fail -eq 0 ] && echo "CLI option checks: all as expected"
exit $fail
