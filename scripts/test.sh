#!/usr/bin/env bash
# The whole test suite, from a fresh clone: installs what the tests need,
# then runs every test in debug. The benchmarks are not built here: their
# code is type-checked by `cargo clippy --all-targets` (.ci/run), and
# building criterion's tree and three more binaries to run each
# benchmark once, untimed, tested nothing else. That the pixels do
# not depend on the build is tested by the browser page's tests: every
# chapter's image from the page's optimised WebAssembly build must be the
# debug binary's, bit for bit (tests/browser/page.test.mjs). The default
# build, without Embree, is a student workspace's (tests/cli/workspace.rs).
# The optional Embree backend is always built and tested here, so that its
# cross-check of every chapter runs in CI (set-up: docs/embree.md).
set -euo pipefail
cd "$(dirname "$0")/.."
# What each step costs, so that a slow CI says where its time went: wall
# time, and the CPU time of the step and all it started (on a shared
# machine the CPU time is the steadier figure).
TIMEFORMAT='test.sh: %1R s wall, %1U s user + %1S s system for the step above'

bash scripts/setup-embree.sh
# A one-off build gains nothing from incremental state, which is a third of
# the target folder (2.3 of 6.8 GB measured): CI machines may be short of disk.
if [[ ${CI:-} == true ]]; then
    export CARGO_INCREMENTAL=0
fi
# Debian packages the tests use, installed with apt where this machine has
# apt and root (or password-less sudo): assimp-testmodels, real OBJ models
# for tests/cli/mesh.rs, bubblewrap, the sandbox of `grade --code`, and GNU
# parallel, which runs grading jobs (tests/cli/grade.rs), and chromium, the
# browser of the page's tests (scripts/test-browser.sh). All are optional
# here: without them those tests say they skipped (the small models the
# tests write themselves still run, the grading tests run unsandboxed and
# their jobs one by one). Never fails the script.
install_package() {
    local package=$1 without=$2 as_root
    if dpkg-query -W -f='${Status}' "$package" 2>/dev/null | grep -q "install ok installed"; then
        return 0
    fi
    if ! command -v apt-get >/dev/null; then
        echo "test.sh: no apt-get; skipping $package ($without)" >&2
        return 0
    fi
    if [[ $(id -u) -eq 0 ]]; then
        as_root=""
    elif command -v sudo >/dev/null && sudo -n true 2>/dev/null; then
        as_root="sudo -n"
    else
        echo "test.sh: installing $package needs root; skipping it ($without)" >&2
        return 0
    fi
    # Without recommends: chromium's pull in a desktop's daemons (avahi)
    # and parallel's sysstat with its timers, none of which a test uses.
    # apt's and dpkg's chatter goes to a log shown only if the install fails.
    local log
    log=$(mktemp)
    echo "test.sh: installing $package (apt-get, as root)" >&2
    # The current package lists first; update them only if that fails.
    if ! $as_root env DEBIAN_FRONTEND=noninteractive apt-get install -y -qq \
        --no-install-recommends -o Dpkg::Use-Pty=0 "$package" >"$log" 2>&1; then
        $as_root apt-get update -qq >>"$log" 2>&1 || true
        $as_root env DEBIAN_FRONTEND=noninteractive apt-get install -y -qq \
            --no-install-recommends -o Dpkg::Use-Pty=0 "$package" >>"$log" 2>&1 || {
            cat "$log" >&2
            echo "test.sh: could not install $package; skipping it ($without)" >&2
        }
    fi
    rm -f "$log"
}
install_package assimp-testmodels "tests/cli/mesh.rs uses its own small models"
install_package bubblewrap "the grade --code tests run unsandboxed"
install_package parallel "the grading-jobs test runs its jobs one by one"
install_package chromium "the browser tests (grade's reports, the page) are skipped"
time cargo test --lib --bins --tests --features embree --no-run
# The lessons are the crate docs: they must build with no broken link, and
# without raylab's source, the answer key (rustdoc leaves old pages in
# place, so those of an earlier build go first).
rm -rf "${CARGO_TARGET_DIR:-target}/doc/src/raylab"
time RUSTDOCFLAGS="-D warnings" cargo doc --no-deps --features embree
bash scripts/check-docs-no-source.sh
# The browser page is built for WebAssembly (in web/target, a folder of
# its own) while the tests below run: they keep the two cores busy only
# about half the time (many wait on a build or a sandbox), and the page's
# compiler, at the lowest priority, takes what they leave.
page_log=$(mktemp)
page_status=$(mktemp)
# Its own process group (setsid), so that a failing test ends it whole.
setsid bash -c 'status=0
    RAYLAB_DOCS="$3" nice -n 19 bash scripts/build-web.sh --out target/web >"$1" 2>&1 || status=$?
    echo "$status" >"$2"' build-web "$page_log" "$page_status" "$PWD/${CARGO_TARGET_DIR:-target}/doc" &
page_build=$!
trap 'kill -- "-$page_build" 2>/dev/null || true; rm -f "$page_log" "$page_status"' EXIT
time cargo test --lib --bins --tests --features embree
time cargo test --doc --features embree
time wait "$page_build"
cat "$page_log" >&2
# grade's HTML reports, then the browser page, in headless Chromium against
# the debug binary the tests above built (skipped, with a message, where
# this machine cannot build the page or has no browser).
time RAYLAB_PAGE_BUILD_STATUS="$(cat "$page_status")" bash scripts/test-browser.sh target/debug/raylab
