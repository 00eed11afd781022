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
# Jobs run at once, each in a process group of its own (so that an
# interrupted run ends them whole), each with its own log, shown whole when
# it ends: the browser page's WebAssembly compile (in web/target, a folder
# of its own) from the start, beside the native build; then, once that
# build is done, the command-line tests, the library's unit tests, the
# other test binaries with the doc tests, and the lessons' build followed
# by the browser tests. One after the other they kept the two cores busy only
# about two thirds of the time (the command-line tests wait on workspace
# builds and sandboxes, the browser tests on the browser, a compile on its
# slowest crate).
jobs_dir=$(mktemp -d)
job_pids=()
declare -A job_names
trap 'for pid in "${job_pids[@]}"; do kill -- "-$pid" 2>/dev/null || true; done; rm -rf "$jobs_dir"' EXIT
export TIMEFORMAT
start_job() {
    local name=$1
    shift
    setsid bash -c 'name=$1; shift
        status=0
        { time "$@"; } >"$name.log" 2>&1 || status=$?
        echo "$status" >"$name.status"' job "$jobs_dir/$name" "$@" &
    job_pids+=("$!")
    job_names[$!]=$name
}
# Waits for every job started and not yet waited for, showing each one's
# log as it ends; a job's status file is written as it ends, and one that
# died without writing it (killed) failed. Polled, as `wait -n` does not
# report a job that ended before it was called (the page's compile may end
# during the build).
failed=()
page_status=0
waited=()
finish_jobs() {
    local pid name status still
    local running=()
    for pid in "${job_pids[@]}"; do
        [[ " ${waited[*]} " == *" $pid "* ]] || running+=("$pid")
    done
    while [[ ${#running[@]} -gt 0 ]]; do
        still=()
        for pid in "${running[@]}"; do
            name=${job_names[$pid]}
            if [[ ! -f $jobs_dir/$name.status ]] && kill -0 "$pid" 2>/dev/null; then
                still+=("$pid")
                continue
            fi
            wait "$pid" 2>/dev/null || true
            waited+=("$pid")
            status=$(cat "$jobs_dir/$name.status" 2>/dev/null || echo 1)
            echo "test.sh: --- $name (exit status $status) ---" >&2
            cat "$jobs_dir/$name.log" >&2
            if [[ $name == page ]]; then
                page_status=$status
                [[ $status -eq 0 || $status -eq 3 ]] && continue
            fi
            [[ $status -eq 0 ]] || failed+=("$name")
        done
        running=("${still[@]}")
        [[ ${#running[@]} -eq 0 ]] || sleep 1
    done
}
# The lessons are the crate docs: they must build with no broken link, and
# without raylab's source, the answer key (rustdoc leaves old pages in
# place, so those of an earlier build go first). Then the page put together
# with those lessons (RAYLAB_DOCS), and grade's HTML reports and the page
# tested in headless Chromium against the debug binary (skipped, with a
# message, where this machine cannot build the page or has no browser).
# In a target folder of their own, shared with .ci/run's clippy: in the
# tests' folder, cargo's lock on it held the command-line tests' workspace
# builds back while the lessons built.
lessons_and_browser() {
    local page_status=$1
    local lint="${CARGO_TARGET_DIR:-target}/lint"
    rm -rf "$lint/doc/src/raylab"
    time RUSTDOCFLAGS="-D warnings" cargo doc --no-deps --features embree --target-dir "$lint" || return 1
    bash scripts/check-docs-no-source.sh "$lint/doc" || return 1
    if [[ $page_status -eq 0 ]]; then
        RAYLAB_DOCS="$PWD/$lint/doc" bash scripts/build-web.sh --out target/web \
            || page_status=$?
    fi
    RAYLAB_PAGE_BUILD_STATUS="$page_status" bash scripts/test-browser.sh target/debug/raylab
}
export -f lessons_and_browser
# Status 3: the page cannot be built here, which the browser tests report
# as a skip.
start_job page bash scripts/build-web.sh --wasm-only
time cargo test --lib --bins --tests --features embree --no-run
# The page's WebAssembly, compiled beside that build.
finish_jobs
# Every integration test binary but cli's, found as cargo finds them.
shopt -s nullglob
other_tests=()
for file in tests/*.rs tests/*/main.rs; do
    name=${file#tests/}
    name=${name%.rs}
    name=${name%/main}
    [[ $name == cli ]] || other_tests+=(--test "$name")
done
# The command-line tests first: the longest, waiting on workspace builds
# and sandboxes, while the others fill the cores. A third test thread goes
# on with the tests that need no workspace while two wait on their build.
start_job cli cargo test --test cli --features embree -- --test-threads 3
start_job lib cargo test --lib --features embree
start_job others bash -c 'cargo test --doc --features embree && cargo test --bins "$@" --features embree' others "${other_tests[@]}"
start_job lessons-browser lessons_and_browser "$page_status"
finish_jobs
if [[ ${#failed[@]} -gt 0 ]]; then
    echo "test.sh: failed: ${failed[*]} (their logs are above)" >&2
    exit 1
fi
