#!/usr/bin/env bash
# Regenerates the reference images (snapshots/chapter-N.png) and their pinned
# hashes (snapshots/chapter-N.snap) after an intended change to the renders.
# Before running it, look at what the failing snapshot test wrote under the
# target folder (target/snapshot-failures/chapter-N.png and
# chapter-N-heatmap.png): a difference nobody intended is a bug, not a new
# reference. After it, review the new PNGs (git diff --stat snapshots/, then
# look at them) before committing.
set -euo pipefail
cd "$(dirname "$0")/.."
RAYLAB_BLESS=1 INSTA_UPDATE=always INSTA_FORCE_PASS=1 cargo test --test pictures snapshots::
git status --short snapshots/ 2>/dev/null || true
