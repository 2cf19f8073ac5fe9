#!/usr/bin/env bash
# Installs the browser tests' Node packages (playwright-core only; it drives Debian's chromium and
# never downloads a browser). Quick when node_modules already matches the lock file.
set -euo pipefail
cd "$(dirname "$0")/../tests/browser"
if [ -d node_modules/playwright-core ] && cmp -s package-lock.json node_modules/.package-lock.json; then
  exit 0
fi
PLAYWRIGHT_SKIP_BROWSER_DOWNLOAD=1 npm ci --no-audit --no-fund --loglevel=error
