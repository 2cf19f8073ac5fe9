#!/usr/bin/env bash
# The target suite's method list must be `tinyphong methods`' (a new method must not escape it).
#   check_methods.sh TINYPHONG METHOD...
set -euo pipefail
tp=$1
shift
listed=$("$tp" methods | cut -f1 | tr '\n' ' ')
if [ "$listed" != "$* " ]; then
  echo "FAIL: tests/target/CMakeLists.txt lists '$*', tinyphong methods lists '$listed'"
  exit 1
fi
echo "the target suite covers all $# methods"
