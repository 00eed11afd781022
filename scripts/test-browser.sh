#!/usr/bin/env bash
# The browser tests: `raylab grade`'s HTML reports
# (tests/browser/report.test.mjs), then the browser page's
# (tests/browser/page.test.mjs), which builds the page
# (scripts/build-web.sh), then drives it in headless Chromium with
# playwright-core from the npm registry (pinned by its lock file). Each
# piece that this machine cannot provide is skipped with a message saying
# what is missing, as scripts/test.sh does for the other optional tools; a
# test that runs and fails fails the script.
# Usage: scripts/test-browser.sh [RAYLAB_BINARY]   (default target/debug/raylab)
# With RAYLAB_PAGE_BUILD_STATUS set, the page in target/web is taken as built
# with that exit status (0 built, 3 cannot be built here, else failed).
set -euo pipefail
cd "$(dirname "$0")/.."
RAYLAB_BIN="$(realpath "${1:-target/debug/raylab}")"
skip() { echo "test-browser: skipping the browser tests: $*" >&2; exit 0; }

[[ -x "$RAYLAB_BIN" ]] || { echo "test-browser: no raylab binary at $RAYLAB_BIN (cargo build first)" >&2; exit 1; }
CHROMIUM="${CHROMIUM:-$(command -v chromium || command -v chromium-browser || true)}"
[[ -n "$CHROMIUM" ]] || skip "no chromium (apt-get install chromium)"
command -v node >/dev/null && command -v npm >/dev/null || skip "no node and npm (apt-get install nodejs npm)"
node_major="$(node -p 'process.versions.node.split(".")[0]')"
[[ $node_major -ge 20 ]] || skip "node $node_major is older than playwright-core needs (20)"

if [[ ! -d tests/browser/node_modules/playwright-core ]]; then
    npm ci --prefix tests/browser --no-audit --no-fund --loglevel=error \
        || skip "npm could not install playwright-core"
fi
# grade's HTML reports need no page: tested first, whether or not the page
# can be built here.
command -v cargo >/dev/null || skip "no cargo on the PATH (the report's class has workspaces to build)"
RAYLAB_BIN="$RAYLAB_BIN" CHROMIUM="$CHROMIUM" RAYLAB_ARTIFACTS=target/browser \
    node --test tests/browser/report.test.mjs

# The page: built here, or already built by scripts/test.sh (which says
# how that build ended in RAYLAB_PAGE_BUILD_STATUS, having shown its log).
if [[ -n ${RAYLAB_PAGE_BUILD_STATUS:-} ]]; then
    status=$RAYLAB_PAGE_BUILD_STATUS
else
    status=0
    # The crate docs scripts/test.sh built just before, if they are there.
    RAYLAB_DOCS="$PWD/target/doc" bash scripts/build-web.sh --out target/web || status=$?
fi
if [[ $status -eq 3 ]]; then
    skip "the page cannot be built here (above)"
elif [[ $status -ne 0 ]]; then
    exit "$status"
fi
RAYLAB_PAGE=target/web RAYLAB_BIN="$RAYLAB_BIN" CHROMIUM="$CHROMIUM" RAYLAB_ARTIFACTS=target/browser \
    node --test tests/browser/page.test.mjs
echo "test-browser: screenshots in target/browser/" >&2
