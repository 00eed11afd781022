#!/usr/bin/env bash
# The student's loop, measured: from saving a chapter file to the verdict of
# that chapter. It makes the answer key (`raylab new --solutions`) in
# WORK_DIR and builds it twice, as generated (incremental release builds)
# and with incremental builds off (CARGO_PROFILE_RELEASE_INCREMENTAL=false),
# each in its own target folder. Then RUNS times (5 by default) it changes
# chapter 1's file (a comment line: the verdict stays a pass) and times
# `cargo run --release --offline -- check --chapter 1` in each, one after
# the other: the rebuild of the student's crate plus the check. It prints
# each time, the load average beside it, and the two medians.
#
# Usage: scripts/edit-to-verdict.sh [WORK_DIR] [RUNS] [--against CHECKOUT]
#   WORK_DIR defaults to target/edit-to-verdict (emptied first).
#   --against CHECKOUT compares two raylabs instead of two build settings:
#   the answer key made by this checkout and by CHECKOUT (another clone or
#   worktree, e.g. an older commit), both incremental, edited and checked
#   alternately so that the machine's load falls on both alike.
# Not part of scripts/test.sh: it measures, and a shared machine's load
# shows in its figures.
set -euo pipefail
root="$(cd "$(dirname "$0")/.." && pwd)"
positional=()
against=""
while [[ $# -gt 0 ]]; do
    case $1 in
        --against)
            against="$(cd "${2:?--against needs a checkout}" && pwd)"
            shift 2
            ;;
        *)
            positional+=("$1")
            shift
            ;;
    esac
done
work="${positional[0]:-$root/target/edit-to-verdict}"
runs="${positional[1]:-5}"
rm -rf "$work"
mkdir -p "$work"

seconds_since() { echo "$(date +%s.%N) - $1" | bc; }
median() { printf '%s\n' "$@" | sort -g | awk '{a[NR]=$1} END {print a[int((NR+1)/2)]}'; }

if [[ -n $against ]]; then
    # edit_and_check WORKSPACE TARGET: one timed edit-and-check, in seconds.
    edit_and_check() {
        local start file
        file=$(ls "$1"/src/chapters/ch01_*.rs)
        echo "// edit" >>"$file"
        start=$(date +%s.%N)
        (cd "$1" && CARGO_TARGET_DIR="$2" cargo run --release --offline --quiet -- check --chapter 1 >/dev/null)
        seconds_since "$start"
    }
    for side in this other; do
        checkout=$root
        [[ $side == other ]] && checkout=$against
        cargo run --quiet --release --manifest-path "$checkout/Cargo.toml" -- new "$work/$side" --solutions >/dev/null
        start=$(date +%s.%N)
        (cd "$work/$side" && CARGO_TARGET_DIR="$work/target-$side" cargo build --release --offline --quiet)
        echo "first build ($side: $(git -C "$checkout" rev-parse --short HEAD)): $(seconds_since "$start") s"
    done
    this_times=()
    other_times=()
    for run in $(seq 1 "$runs"); do
        this=$(edit_and_check "$work/this" "$work/target-this")
        other=$(edit_and_check "$work/other" "$work/target-other")
        this_times+=("$this")
        other_times+=("$other")
        echo "edit $run: this ${this} s, other ${other} s (load $(cut -d' ' -f1 /proc/loadavg))"
    done
    echo "median of $runs, from saving chapter 1 to its verdict (incremental release builds):"
    echo "  this checkout ($(git -C "$root" rev-parse --short HEAD)):  $(median "${this_times[@]}") s"
    echo "  other checkout ($(git -C "$against" rev-parse --short HEAD)): $(median "${other_times[@]}") s"
    exit 0
fi

workspace="$work/answer-key"
cargo run --quiet --release --manifest-path "$root/Cargo.toml" -- new "$workspace" --solutions >/dev/null
cd "$workspace"
# The first chapter's file, whatever the registry names it.
file=$(ls src/chapters/ch01_*.rs)

# check_once TARGET INCREMENTAL: one timed edit-and-check, in seconds.
check_once() {
    local start
    start=$(date +%s.%N)
    CARGO_TARGET_DIR="$1" CARGO_PROFILE_RELEASE_INCREMENTAL="$2" \
        cargo run --release --offline --quiet -- check --chapter 1 >/dev/null
    seconds_since "$start"
}

for variant in incremental plain; do
    incremental=true
    [[ $variant == plain ]] && incremental=false
    start=$(date +%s.%N)
    CARGO_TARGET_DIR="$work/target-$variant" CARGO_PROFILE_RELEASE_INCREMENTAL=$incremental \
        cargo build --release --offline --quiet
    echo "first build ($variant, raylab included): $(seconds_since "$start") s"
done
incremental_times=()
plain_times=()
for run in $(seq 1 "$runs"); do
    echo "// edit $run" >>"$file"
    on=$(check_once "$work/target-incremental" true)
    echo "// edit $run again" >>"$file"
    off=$(check_once "$work/target-plain" false)
    incremental_times+=("$on")
    plain_times+=("$off")
    echo "edit $run: incremental ${on} s, plain ${off} s (load $(cut -d' ' -f1 /proc/loadavg))"
done
echo "median of $runs, from saving chapter 1 to its verdict:"
echo "  incremental (as raylab new writes it): $(median "${incremental_times[@]}") s"
echo "  plain release build:                   $(median "${plain_times[@]}") s"

# What the incremental build costs the renders: the renderer compiled in
# more, smaller units optimises less. Chapter 8 at 320x240 on one thread,
# median of 3, both binaries, twice each, alternately.
bench_args=(bench --chapter 8 --width 320 --height 240 --runs 3 --threads 1)
package=$(basename "$workspace")
for round in 1 2; do
    for variant in incremental plain; do
        echo "render cost ($variant, round $round): $("$work/target-$variant/release/$package" "${bench_args[@]}" 2>&1 | tail -1)"
    done
done
