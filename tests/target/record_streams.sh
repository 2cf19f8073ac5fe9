#!/usr/bin/env bash
# Records one method's command stream of every given scene (build step of tests/target):
#   record_streams.sh TINYPHONG SCENES_DIR SIZE METHOD OUT_DIR [--small-part] SCENE...
# (SIZE WxH, or "own": each scene's own resolution) writes OUT_DIR/METHOD/SCENE.tpcmd with one `tinyphong record` run (its start-up, not the
# recording, is what costs: one run per method, not per stream). --small-part is record's: the
# frame a part with little RAM draws (docs/TARGET.md, "A small part").
set -euo pipefail
tp=$1 scenes=$2 size=$3 method=$4 out=$5
shift 5
part_opt=()
if [ "${1:-}" = --small-part ]; then
  part_opt=(--small-part)
  shift
fi
mkdir -p "$out/$method"
files=()
for scene in "$@"; do files+=("$scenes/$scene.json"); done
size_opt=(--size "$size")
[ "$size" = own ] && size_opt=()
"$tp" record "${files[@]}" --method "$method" "${size_opt[@]}" "${part_opt[@]}" --dir "$out/$method" \
  >/dev/null
