#!/usr/bin/env bash
# The main job: build the emulated device (release) and run it.
set -euo pipefail
cd "$(dirname "$0")/.."
bash scripts/install-deps.sh
cmake --preset release >/dev/null
cmake --build --preset release -j "$(nproc)"
if [ -x build/release/server/tinyphong-server ]; then
  exec build/release/server/tinyphong-server "$@"
fi
# Until the server exists: render the default scene with the device and say where it is.
out=${TP_OUT:-build/release/teapot.png}
build/release/host/tinyphong render scenes/teapot.json --method kb-adaptive -o "$out"
echo "rendered: $(realpath "$out")"
