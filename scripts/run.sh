#!/usr/bin/env bash
# The main job: build the emulated device (release) and run it.
set -euo pipefail
cd "$(dirname "$0")/.."
bash scripts/install-deps.sh
cmake --preset release >/dev/null
cmake --build --preset release -j "$(nproc)"
exec build/release/server/tinyphong-server "$@"
