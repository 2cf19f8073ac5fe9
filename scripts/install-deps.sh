#!/usr/bin/env bash
# Installs everything tinyphong builds, tests and runs with, from Debian 12's packages.
# Idempotent and quick when everything is present: apt-get runs only for what is missing.
# Needs root (or sudo) when something is missing.
set -euo pipefail

packages=(
  # toolchain
  build-essential cmake ninja-build pkg-config git
  # host libraries
  libglm-dev libopenimageio-dev openimageio-tools libopenexr-dev
  libboost-dev nlohmann-json3-dev libcli11-dev libtinyobjloader-dev
  # tests and benchmarks; Mesa's llvmpipe through OSMesa is the benchmark's peer (host/llvmpipe.hpp)
  libgtest-dev libgmock-dev libbenchmark-dev libosmesa6-dev
  # integer-only proof and the Cortex-M images: the cross toolchain
  gcc-arm-none-eabi libnewlib-arm-none-eabi libstdc++-arm-none-eabi-newlib binutils-arm-none-eabi
  # the Cortex-M images run under QEMU (tests/target, label target)
  qemu-system-arm
  # browser end-to-end tests
  chromium
  # tooling used by the scripts
  python3 curl
  # formatting check (tests/format)
  clang-format-14
  # fuzz targets (tests/fuzz, the `fuzz` preset): clang 14 and its libFuzzer runtime
  clang libclang-rt-14-dev
)

missing=()
for p in "${packages[@]}"; do
  if ! dpkg-query -W -f='${Status}' "$p" 2>/dev/null | grep -q "install ok installed"; then
    missing+=("$p")
  fi
done

# Node.js and npm drive playwright-core; the machine image may carry its own node (newer than
# Debian's, and Debian's npm package conflicts with it), so Debian's are installed only if absent.
if ! command -v node >/dev/null 2>&1 || ! command -v npm >/dev/null 2>&1; then
  missing+=(nodejs npm)
fi

if [ ${#missing[@]} -eq 0 ]; then
  echo "install-deps: all ${#packages[@]} packages present"
  exit 0
fi

SUDO=""
if [ "$(id -u)" -ne 0 ]; then SUDO="sudo"; fi
echo "install-deps: installing ${missing[*]}"
export DEBIAN_FRONTEND=noninteractive
$SUDO apt-get update -qq
$SUDO apt-get install -y -qq --no-install-recommends "${missing[@]}" >/dev/null
echo "install-deps: done"
