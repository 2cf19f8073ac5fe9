#!/usr/bin/env bash
# Records one method's command stream of every given scene (build step of tests/target):
#   record_streams.sh TINYPHONG SCENES_DIR SIZE METHOD OUT_DIR SCENE...
# writes OUT_DIR/METHOD/SCENE.tpcmd with `tinyphong record`.
set -euo pipefail
tp=$1 scenes=$2 size=$3 method=$4 out=$5
shift 5
mkdir -p "$out/$method"
for scene in "$@"; do
  "$tp" record "$scenes/$scene.json" --method "$method" --size "$size" \
    -o "$out/$method/$scene.tpcmd" >/dev/null
done
