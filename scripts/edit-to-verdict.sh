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
# Usage: scripts/edit-to-verdict.sh [WORK_DIR] [RUNS]
#   WORK_DIR defaults to target/edit-to-verdict (emptied first).
# Not part of scripts/test.sh: it measures, and a shared machine's load
# shows in its figures.
set -euo pipefail
root="$(cd "$(dirname "$0")/.." && pwd)"
work="${1:-$root/target/edit-to-verdict}"
runs="${2:-5}"
rm -rf "$work"
mkdir -p "$work"
workspace="$work/answer-key"
cargo run --quiet --release --manifest-path "$root/Cargo.toml" -- new "$workspace" --solutions >/dev/null
cd "$workspace"
# The first chapter's file, whatever the registry names it.
file=$(ls src/chapters/ch01_*.rs)

seconds_since() { echo "$(date +%s.%N) - $1" | bc; }

# check_once TARGET INCREMENTAL: one timed edit-and-check, in seconds.
check_once() {
    local start
    start=$(date +%s.%N)
    CARGO_TARGET_DIR="$1" CARGO_PROFILE_RELEASE_INCREMENTAL="$2" \
        cargo run --release --offline --quiet -- check --chapter 1 >/dev/null
    seconds_since "$start"
}

median() { printf '%s\n' "$@" | sort -g | awk '{a[NR]=$1} END {print a[int((NR+1)/2)]}'; }

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
