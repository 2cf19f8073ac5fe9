#!/usr/bin/env bash
# Runs `tinyphong render FILE` and passes only if it fails with exit status 1, writes no image,
# and prints a message matching PATTERN (an extended regex).
set -u
tool=$1 file=$2 pattern=$3
out=$(mktemp -d)
trap 'rm -rf "$out"' EXIT
msg=$("$tool" render "$file" -o "$out/img.png" 2>&1)
rc=$?
echo "$msg"
[ $rc -eq 1 ] || { echo "expected exit status 1, got $rc"; exit 1; }
[ ! -e "$out/img.png" ] || { echo "an image was written for a bad scene"; exit 1; }
echo "$msg" | grep -Eq "$pattern" || { echo "message does not match: $pattern"; exit 1; }
