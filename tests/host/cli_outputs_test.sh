#!/usr/bin/env bash
# The CLI never writes an output over one of its inputs: `record`, `render` or `reference` over
# the scene file or a mesh it names, `compare --diff` over either image it compares, `replay -o`
# over its stream. The same file by any name is refused (the path itself, ./dir/../, a symbolic
# link, a hard link), with exit status 2, a message naming the input and every file left as it
# was; with several scenes a bad one (unreadable, or refused by the device's checks) makes `record`
# write no stream at all; `reference` refuses an --exr that is its -o. And a write that fails
# part-way keeps the old file, for every image and file the CLI writes. Good outputs still work.
# Usage: cli_outputs_test.sh TINYPHONG SCENES_DIR
set -euo pipefail
tp=$1 scenes=$2
work=$(mktemp -d)
trap 'rm -rf "$work"' EXIT
fail=0

cp "$scenes/triangle.json" "$work/scene.json"
cp "$scenes/quad.obj" "$work/quad.obj"
cat > "$work/mesh.json" <<'JSON'
{
  "camera": {"type": "orthographic", "extents": [-2, 2, -2, 2]},
  "lights": [{"type": "directional", "direction": [0, 0, 1]}],
  "meshes": [{"obj": "quad.obj"}]
}
JSON
mkdir "$work/sub" "$work/dir"
ln -s scene.json "$work/link.tpcmd"
ln "$work/scene.json" "$work/hard.tpcmd"
ln -s quad.obj "$work/obj-link.tpcmd"
ln -s scene.json "$work/link.png"
ln -s scene.json "$work/link.exr"
cp -a "$work" "$work.before"
trap 'rm -rf "$work" "$work.before"' EXIT

# refused NAME TEXT ARGS...: exit status 2, TEXT on stderr, no file of the work folder changed
# and none added.
refused() {
  local name=$1 text=$2 out status=0
  shift 2
  out=$("$tp" "$@" 2>&1 >/dev/null) || status=$?
  if [ "$status" != 2 ] || ! grep -qF -- "$text" <<<"$out"; then
    echo "FAIL: $name: status $status, '$out'"; fail=1
  elif ! diff -r --no-dereference "$work.before" "$work" >/dev/null; then
    echo "FAIL: $name: a file changed: $(diff -rq --no-dereference "$work.before" "$work")"; fail=1
  else
    echo "ok: $name: $out"
  fi
}

cd "$work"
refused "record over its scene" "scene.json is the scene file scene.json: nothing written" \
  record scene.json -o scene.json
refused "record over its scene, by another path" "is the scene file scene.json" \
  record scene.json -o sub/../scene.json
refused "record over its scene, by an absolute path" "is the scene file scene.json" \
  record scene.json -o "$work/scene.json"
refused "record over its scene, through a symbolic link" \
  "link.tpcmd is the scene file scene.json" record scene.json -o link.tpcmd
refused "record over its scene, through a hard link" \
  "hard.tpcmd is the scene file scene.json" record scene.json -o hard.tpcmd
refused "record over the scene's mesh" "quad.obj is the mesh quad.obj of mesh.json" \
  record mesh.json -o quad.obj
refused "record over the scene's mesh, through a link" "obj-link.tpcmd is the mesh quad.obj of mesh.json" \
  record mesh.json -o obj-link.tpcmd
refused "render over its scene, through a link" "link.png is the scene file scene.json" \
  render scene.json -o link.png
refused "reference over its scene, through a link" "link.png is the scene file scene.json" \
  reference scene.json -o link.png
refused "reference --exr over its scene, through a link" "link.exr is the scene file scene.json" \
  reference scene.json -o ref.png --exr link.exr
refused "reference --exr over its own -o" "--exr out.exr is -o ./out.exr, the image it would replace" \
  reference scene.json -o ./out.exr --exr out.exr
# --dir: DIR/scene.tpcmd is a link to the other scene's file.
ln -s ../mesh.json dir/scene.tpcmd
rm -rf "$work.before" && cp -a "$work" "$work.before"
refused "record --dir over another scene" "dir/scene.tpcmd is the scene file mesh.json" \
  record mesh.json scene.json --dir dir
rm dir/scene.tpcmd
# --dir: two streams that exist as one file (hard links) would be written one over the other.
cp scene.json a.json
cp scene.json b.json
echo old > dir/a.tpcmd
ln dir/a.tpcmd dir/b.tpcmd
rm -rf "$work.before" && cp -a "$work" "$work.before"
refused "record --dir to two names of one file" "a.json and b.json would both be recorded to dir/b.tpcmd" \
  record a.json b.json --dir dir
rm a.json b.json dir/a.tpcmd dir/b.tpcmd
# A bad scene after a good one: every scene is read and recorded before any stream is written.
# bad.json does not parse; far.json parses, but its light is beyond the device's Q15.16 eye
# space, which only the device's checks of the scene find.
echo '{' > bad.json
cat > far.json <<'JSON'
{
  "camera": {"type": "perspective", "position": [-10000, -10000, -10000], "target": [0, 0, 0],
             "up": [0, 1, 0], "fov_y": 30},
  "lights": [{"type": "point", "position": [10000, 10000, 10000]}],
  "meshes": [{"generator": "triangle"}]
}
JSON
for second in bad.json far.json; do
  status=0
  out=$("$tp" record scene.json "$second" --dir dir 2>&1 >/dev/null) || status=$?
  if [ "$status" != 1 ] || ! grep -q "$second" <<<"$out" || [ -n "$(ls -A dir)" ]; then
    echo "FAIL: a bad second scene $second: status $status, '$out', dir holds '$(ls -A dir)'"
    fail=1
  else
    echo "ok: a bad second scene $second writes no stream: $out"
  fi
done
rm bad.json far.json

"$tp" render scene.json --method gouraud --size 64x48 -o a.png >/dev/null
"$tp" render scene.json --method flat --size 64x48 -o b.png >/dev/null
ln -s b.png b-link.png
rm -rf "$work.before" && cp -a "$work" "$work.before"
refused "compare --diff over the first image" "a.png is the first image a.png: nothing written" \
  compare a.png b.png --diff a.png
refused "compare --diff over the second image, by a link" \
  "b-link.png is the second image b.png" compare a.png b.png --diff b-link.png
refused "compare --diff over the second image, by another path" "is the second image b.png" \
  compare a.png b.png --diff ./sub/../b.png
"$tp" record scene.json --size 64x48 -o s.tpcmd >/dev/null
ln -s s.tpcmd s-link.png
rm -rf "$work.before" && cp -a "$work" "$work.before"
refused "replay -o over its stream, through a link" "s-link.png is the stream s.tpcmd" \
  replay s.tpcmd -o s-link.png

# A write that fails part-way (here the file size limit, 2 KiB: every file below is larger) keeps
# the file that was there, whole, and leaves no FILE.part: each writer encodes in memory and
# renames a finished FILE.part over FILE (host/replace_file.hpp). OpenImageIO's PNG writer does
# not report such a failure: the old tool wrote 2 KiB of PNG, lost the old image and exited 0.
# kept NAME FILE STATUS ARGS...: exit STATUS, "FILE: cannot write: File too large" on stderr, FILE
# (or the file it links to) as before; then the same command without the limit replaces it, with
# FILE's permissions (751: no umask makes that of a new file's 666), and leaves no FILE.part.
kept() {
  local name=$1 file=$2 want=$3 out status=0 link=no
  shift 3
  [ -L "$file" ] && link=yes
  echo old > "$file"
  chmod 751 "$file"
  out=$(trap '' XFSZ; ulimit -f 2; "$tp" "$@" 2>&1 >/dev/null) || status=$?
  if [ "$status" != "$want" ] || ! grep -qF -- "$file: cannot write: File too large" <<<"$out" ||
     [ "$(cat "$file")" != old ] || [ -e "$file.part" ]; then
    echo "FAIL: $name: status $status, '$out', $file holds $(wc -c < "$file") bytes or $file.part left"
    fail=1
  elif "$tp" "$@" >/dev/null 2>&1; [ "$(head -c 3 "$file")" = old ] || [ -e "$file.part" ] ||
       [ "$(stat -L -c %a "$file")" != 751 ] || { [ "$link" = yes ] && [ ! -L "$file" ]; }; then
    echo "FAIL: $name: without the limit $file was not replaced, kept no 751, lost its link or" \
         "$file.part was left"
    fail=1
  else
    echo "ok: $name: $(tail -n 1 <<<"$out")"
  fi
  rm -f "$file"
}
kept "render, a failed write" big.png 1 render scene.json --size 160x120 -o big.png
kept "reference, a failed write" big.png 1 reference scene.json --size 160x120 -o big.png
ln -s /dev/null sub/null.png  # the PNG through a link to a device, beyond the limit's reach
kept "reference --exr, a failed write" big.exr 1 \
  reference scene.json --size 160x120 -o sub/null.png --exr big.exr
"$tp" render scene.json --method phong --size 160x120 -o sub/g.png >/dev/null
"$tp" render scene.json --method flat --size 160x120 -o sub/f.png >/dev/null
kept "compare --diff, a failed write" big.png 1 compare sub/g.png sub/f.png --diff big.png
"$tp" record scene.json --size 160x120 -o sub/big.tpcmd >/dev/null
kept "replay -o, a failed write" big.png 1 replay sub/big.tpcmd -o big.png
mkdir images
kept "stress --images, a failed write" images/ab-min.reference.png 3 \
  stress --cases ab-min --methods flat --images images
kept "stress --json, a failed write" big.json 3 \
  stress --cases ab-min --methods flat,gouraud,phong,duff,brown --json big.json
# A run killed while it writes (here by the file size limit's signal, as Ctrl-C would) leaves the
# old file and nothing beside it, so the next run is not refused for a FILE.part: the bytes go to a
# file with no name (O_TMPFILE) until all of them are written. A file system without unnamed files
# falls back to a named FILE.part, which a killed run leaves: then the check says it did not run.
if python3 -c 'import os, sys; os.close(os.open(sys.argv[1], os.O_TMPFILE | os.O_WRONLY))' . 2>/dev/null; then
  echo old > big.png
  # (the shell's own "File size limit exceeded" line to /dev/null as well)
  status=$( (ulimit -f 2; exec "$tp" render scene.json --size 160x120 -o big.png) >/dev/null 2>&1
           echo $?) 2>/dev/null
  left=$(ls -A | grep '^big\.png.' | tr '\n' ' ' || true)
  if [ "$status" != 153 ] || [ "$(cat big.png)" != old ] || [ -n "$left" ]; then
    echo "FAIL: a run killed while it writes: status $status (153: SIGXFSZ), big.png holds" \
         "$(wc -c < big.png) bytes, left: '$left'"
    fail=1
  elif ! "$tp" render scene.json --size 160x120 -o big.png >/dev/null 2>&1 || [ "$(head -c 3 big.png)" = old ]; then
    echo "FAIL: the run after a killed one did not replace big.png"; fail=1
  else
    echo "ok: a run killed while it writes leaves the old file and nothing beside it"
  fi
  rm -f big.png
else
  echo "not run: this file system makes no unnamed files (O_TMPFILE): a killed run leaves FILE.part"
fi
# Through a symbolic link: the file it names is kept, then replaced beside itself; the link stays.
echo old > sub/real.png
ln -s real.png sub/link.png
kept "render through a link, a failed write" sub/link.png 1 \
  render scene.json --size 160x120 -o sub/link.png
[ -e sub/real.png.part ] && { echo "FAIL: render through a link left real.png.part"; fail=1; }
# A new file at the end of a link: a failed write leaves no file there; a good one makes it.
ln -s new.png sub/dangling.png
status=0
out=$(trap '' XFSZ; ulimit -f 2; "$tp" render scene.json --size 160x120 -o sub/dangling.png 2>&1) ||
  status=$?
if [ "$status" != 1 ] || [ -e sub/new.png ] || [ -e sub/new.png.part ] || [ ! -L sub/dangling.png ]; then
  echo "FAIL: a failed write through a dangling link: status $status, or a file left"; fail=1
elif ! "$tp" render scene.json --size 160x120 -o sub/dangling.png >/dev/null || [ ! -s sub/new.png ]; then
  echo "FAIL: a write through a dangling link made no file"; fail=1
else
  echo "ok: a new file at the end of a link: none after a failed write, made by a good one"
fi
rm -rf sub/* images

# Good outputs: a new stream, a new difference image, both real files.
"$tp" record scene.json --size 64x48 -o new.tpcmd >/dev/null && [ -s new.tpcmd ] ||
  { echo "FAIL: record to a new file"; fail=1; }
# /dev/stdout names a descriptor (here a pipe), written as it is: the stream alone, record's line
# on standard error (it was written into the stream, which replay then refused; found by review,
# 2026-12-08). A stream recorded into a pipe replays from the pipe.
"$tp" record scene.json --size 64x48 -o /dev/stdout 2>piped.err | cat > piped.out || true
cmp -s piped.out new.tpcmd && grep -q "words -> /dev/stdout" piped.err ||
  { echo "FAIL: record -o /dev/stdout: $(cat piped.err)"; fail=1; }
hash_file=$("$tp" replay new.tpcmd --hash | cut -d' ' -f1)
hash_pipe=$("$tp" record scene.json --size 64x48 -o /dev/stdout 2>/dev/null |
  "$tp" replay /dev/stdin --hash | cut -d' ' -f1) || true
[ -n "$hash_file" ] && [ "$hash_pipe" = "$hash_file" ] ||
  { echo "FAIL: record -o /dev/stdout | replay /dev/stdin: '$hash_pipe' vs '$hash_file'"; fail=1; }
# Only the chosen command's own outputs count: `methods > out.png`, render's default output,
# keeps the list on standard output.
"$tp" methods > out.png 2>methods.err && grep -q "^kb-adaptive" out.png && [ ! -s methods.err ] ||
  { echo "FAIL: methods > out.png: the list went elsewhere"; fail=1; }
rm -f out.png methods.err
"$tp" record mesh.json scene.json --size 64x48 --dir dir >/dev/null &&
  [ -s dir/mesh.tpcmd ] && [ -s dir/scene.tpcmd ] || { echo "FAIL: record --dir"; fail=1; }
"$tp" compare a.png b.png --diff diff.png >/dev/null && [ -s diff.png ] ||
  { echo "FAIL: compare --diff to a new file"; fail=1; }
# compare --worst N lists the start of the longer lists: ties in row order, then column (a
# partial sort left them in any order; found by review, 2026-12-07).
worst() { "$tp" compare a.png b.png --worst "$1" | sed -n '/^worst pixels/,$p' | tail -n +2; }
if [ "$(worst 5)" != "$(worst 100000 | head -n 5)" ] || [ "$(worst 5 | wc -l)" != 5 ]; then
  echo "FAIL: compare --worst 5 is not the start of --worst 100000"; fail=1
else
  echo "ok: compare --worst 5 is the start of --worst 100000"
fi
# A --row outside the images is refused before anything is written: the old tool wrote the
# difference image over the file and then refused the row (found by review, 2026-12-07).
echo precious > keep.png
status=0
out=$("$tp" compare a.png b.png --diff keep.png --row 100000 2>&1) || status=$?
if [ "$status" != 2 ] || [ "$(cat keep.png)" != precious ] || ! grep -qF -- "--row 100000 outside" <<<"$out"; then
  echo "FAIL: compare --row out of range: status $status, '$out', or keep.png changed"; fail=1
else
  echo "ok: compare --row out of range refused, --diff's file kept: $out"
fi
cmp -s scene.json "$scenes/triangle.json" && cmp -s quad.obj "$scenes/quad.obj" ||
  { echo "FAIL: an input changed"; fail=1; }

[ $fail -eq 0 ] && echo "outputs over inputs: all refused"
exit $fail
