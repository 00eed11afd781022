#!/usr/bin/env bash
# The mutation score of the course's checks: how many small changes to the
# reference chapters (an operator flipped, a constant changed, a body
# replaced by a default) the checks notice.
#
# It generates the answer key (`raylab new --solutions`), then runs
# cargo-mutants on that workspace's chapter files (src/chapters/chNN_*.rs),
# with the workspace's own `cargo test` as the test: tests/check.rs, one
# `raylab::check::assert_chapter` per chapter, exactly what a student runs.
# A mutant is caught when some chapter's check fails. It prints caught,
# missed, timeouts and unviable counts, the score over viable mutants, and
# the missed mutants (the survivors worth reading).
#
# Usage: scripts/mutation-score.sh [WORK_DIR] [extra cargo-mutants options]
#   WORK_DIR defaults to target/mutation; it is emptied first. Extra options
#   go to cargo mutants, e.g. `--jobs 2` or `--file src/chapters/ch02_sphere.rs`
#   to look at one chapter.
# Slow: every mutant rebuilds the workspace and runs all the checks. It is
# not part of scripts/test.sh.
set -euo pipefail
root="$(cd "$(dirname "$0")/.." && pwd)"
work="$root/target/mutation"
if [[ $# -gt 0 && $1 != -* ]]; then
    work="$1"
    shift
fi

if ! cargo mutants --version >/dev/null 2>&1; then
    echo "cargo-mutants is not installed; installing it (cargo install cargo-mutants --locked)"
    cargo install cargo-mutants --locked
fi

rm -rf "$work"
mkdir -p "$work"
workspace="$work/answer-key"
cargo run --quiet --manifest-path "$root/Cargo.toml" -- new "$workspace" --solutions

# The workspace resolves offline from raylab's Cargo.lock. The glob keeps
# src/chapters/mod.rs (generated glue, not a lesson) out.
# The checks count both levels here (RAYLAB_CHECK_ROBUST=1): a mutant that
# only the hard cases notice is caught. `sphere_roots` is the answer key's
# public helper for `raylab probe`, which no Chapters method calls: its
# mutants could never be caught, so they are left out.
status=0
RAYLAB_CHECK_ROBUST=1 cargo mutants \
    --dir "$workspace" \
    --file 'src/chapters/ch*.rs' \
    --exclude-re 'sphere_roots' \
    --output "$work" \
    --cargo-arg=--offline \
    "$@" || status=$?
# cargo-mutants exits 2 when mutants were missed and 3 on timeouts: those
# are results to report. Anything else (1: bad usage, 4: the unmutated
# workspace fails its own checks) means no score.
if [[ $status -ne 0 && $status -ne 2 && $status -ne 3 ]]; then
    echo "cargo mutants failed (exit $status); see $work/mutants.out/" >&2
    exit "$status"
fi

out="$work/mutants.out"
count() { if [[ -s "$out/$1.txt" ]]; then wc -l <"$out/$1.txt"; else echo 0; fi; }
caught=$(count caught)
missed=$(count missed)
timeouts=$(count timeout)
unviable=$(count unviable)
viable=$((caught + missed + timeouts))
echo
echo "mutation score of the checks on the reference chapters"
echo "  caught:   $caught"
echo "  missed:   $missed"
echo "  timeouts: $timeouts (counted as caught: the checks did not pass)"
echo "  unviable: $unviable (did not build; not counted)"
if [[ $viable -gt 0 ]]; then
    # Integer arithmetic, one decimal.
    per_mille=$(((caught + timeouts) * 1000 / viable))
    echo "  score:    $((per_mille / 10)).$((per_mille % 10))% of $viable viable mutants"
fi
if [[ $missed -gt 0 ]]; then
    echo
    echo "missed mutants (the checks passed with these changes):"
    sed 's/^/  /' "$out/missed.txt"
fi
echo
echo "details: $out/ (outcomes.json, and a log per mutant)"
