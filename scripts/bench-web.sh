#!/usr/bin/env bash
# The browser page's render time against raylab render's, on one thread
# each (one Web Worker; --threads 1), the same chapter and size, measured
# side by side in one run: prints both medians and their ratio.
# Usage: scripts/bench-web.sh [CHAPTER (8)] [WIDTH (320)] [REPEATS (7)]
# Needs what scripts/test-browser.sh needs (the page built, chromium, npm).
set -euo pipefail
cd "$(dirname "$0")/.."
cargo build --release -q
bash scripts/build-web.sh --out target/web
[[ -d tests/browser/node_modules/playwright-core ]] \
    || npm ci --prefix tests/browser --no-audit --no-fund --loglevel=error
RAYLAB_PAGE=target/web RAYLAB_BIN=target/release/raylab \
    node tests/browser/bench.mjs "${1:-8}" "${2:-320}" "${3:-7}"
