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
#   go to cargo mutants, e.g. `--shard 0/8` for a deterministic eighth,
#   `--re 'ch02_'` for one chapter or `--re rescaled_roots` for one
#   function (the regex is matched against the whole mutant name, file and
#   function included), or `--jobs 2`. (`--file` adds files to the chapter
#   glob below rather than narrowing it.) `--iterate` keeps WORK_DIR's
#   earlier results and tests only what they did not catch: after adding
#   check cases, it gives the whole run's score in the time of the misses.
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

# `--iterate` (cargo-mutants' own option) tests only the mutants that no
# earlier run in WORK_DIR caught: mutants.out stays, the rest is remade.
iterate=false
list_args=()
for arg in "$@"; do
    if [[ $arg == --iterate ]]; then
        iterate=true
    else
        list_args+=("$arg")
    fi
done
if $iterate && [[ -d $work/mutants.out ]]; then
    find "$work" -mindepth 1 -maxdepth 1 ! -name mutants.out -exec rm -rf {} +
else
    rm -rf "$work"
fi
mkdir -p "$work"
workspace="$work/answer-key"
cargo run --quiet --manifest-path "$root/Cargo.toml" -- new "$workspace" --solutions

# The workspace resolves offline from raylab's Cargo.lock. The glob keeps
# src/chapters/mod.rs (generated glue, not a lesson) out.
# The checks count both levels here (RAYLAB_CHECK_ROBUST=1): a mutant that
# only the hard cases notice is caught.
#
# Left out: the answer key's functions that nothing in the workspace calls.
# The chapter files carry them for raylab itself (the lessons' comparisons:
# `--sphere-formula textbook`, `--triangle-test moller-trumbore`,
# `raylab probe`'s roots, the critical angle the lesson prints), and raylab
# uses its own copies; in the workspace they are dead code, their mutants
# could never be caught, and students are not asked to write them. Each
# entry is the function and how many lines of the workspace's src/ name it
# (`name(`, comments aside): its definition, plus calls from other dead
# functions (`first_root_in` is called by `intersect_sphere_textbook`
# only). If a count changes, someone calls it now: the script stops, and
# the function must be mutated like the others.
unreachable=(
    sphere_roots:1
    intersect_sphere_textbook:1
    first_root_in:2
    critical_angle:1
    intersect_triangle_moller_trumbore:1
)
names=()
for entry in "${unreachable[@]}"; do
    name=${entry%%:*}
    expected=${entry##*:}
    found=$(grep -rE "\b$name\(" "$workspace/src" | grep -cvE '^[^:]*:[[:space:]]*//' || true)
    if [[ $found -ne $expected ]]; then
        echo "$name( is named on $found lines of the workspace's src/, not $expected:" >&2
        echo "it may be reachable now; mutate it (remove it from 'unreachable')." >&2
        exit 1
    fi
    names+=("$name")
done
exclude="\\b($(IFS='|'; echo "${names[*]}"))\\b"
# A timeout unless one is given: the checks take about 2 s unmutated, but
# on shared, loaded cores the time cargo-mutants derives from that (20 s)
# has cut off mutants that were only slow. 120 s is what the figures in
# docs/course.md were measured with; a mutant that loops still ends.
timeout=(--timeout 120)
for arg in "$@"; do
    if [[ $arg == --timeout || $arg == --timeout=* ]]; then
        timeout=()
    fi
done

status=0
RAYLAB_CHECK_ROBUST=1 cargo mutants \
    --dir "$workspace" \
    --file 'src/chapters/ch*.rs' \
    --exclude-re "$exclude" \
    --output "$work" \
    --cargo-arg=--offline \
    "${timeout[@]}" \
    "$@" || status=$?
# cargo-mutants exits 2 when mutants were missed and 3 on timeouts: those
# are results to report. Anything else (1: bad usage, 4: the unmutated
# workspace fails its own checks) means no score.
if [[ $status -ne 0 && $status -ne 2 && $status -ne 3 ]]; then
    echo "cargo mutants failed (exit $status); see $work/mutants.out/" >&2
    exit "$status"
fi

# Mutants argued to be equivalent within rounding: each changes an answer
# only where the exact answer is within the rounding of the decision it
# touches (a tangent ray, a ray parallel to a plane as far as f32 can tell),
# where the checks accept either answer, as they must to accept every
# correct f32 formula, or changes no answer a Chapters method can return
# (dead code, the sign of a zero, a value the caller ignores). They stay in the run and in the first score; the
# second score leaves them out. docs/course.md ("Mutation score") gives the
# argument for each. The names carry the answer key's line numbers: if a
# chapter file changes, re-derive its list (the script says how many of
# them it found among the mutants it ran).
# Each chapter folder's equivalent-mutants.txt lists them, with the
# argument for each, as `line:column: mutation` in that chapter's file.
equivalent=()
for listed in "$root"/chapters/[0-9][0-9]_*/equivalent-mutants.txt; do
    folder=$(basename "$(dirname "$listed")")
    while IFS= read -r line; do
        [[ -z $line || $line == '#'* ]] && continue
        equivalent+=("src/chapters/ch$folder.rs:$line")
    done <"$listed"
done
# The score counts the mutants of the answer key as it is now (with the
# same filters): under --iterate the ones caught by earlier runs are in
# previously_caught.txt, and mutants of code that changed since then no
# longer exist and must not count.
details="$work/mutants.out"
out="$work/score"
mkdir -p "$out"
cargo mutants --list --dir "$workspace" --file 'src/chapters/ch*.rs' \
    --exclude-re "$exclude" "${list_args[@]}" >"$out/current.txt"
for kind in caught missed timeout unviable; do
    sources=("$details/$kind.txt")
    if [[ $kind == caught ]]; then
        sources+=("$details/previously_caught.txt")
    fi
    # A list cargo-mutants did not write (previously_caught.txt outside
    # --iterate) is empty, not an error.
    { cat "${sources[@]}" 2>/dev/null || true; } | sort -u | { grep -Fxf "$out/current.txt" || true; } >"$out/$kind.txt"
done
untested=$(cat "$out"/{caught,missed,timeout,unviable}.txt | sort -u | { grep -cvxFf - "$out/current.txt" || true; })
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
if [[ $untested -gt 0 ]]; then
    echo "  untested: $untested (no outcome on record: unviable in an earlier run, or the run was cut short)"
fi
# Integer arithmetic, one decimal.
percent() { local per_mille=$(($1 * 1000 / $2)); echo "$((per_mille / 10)).$((per_mille % 10))%"; }
if [[ $viable -gt 0 ]]; then
    echo "  score:    $(percent $((caught + timeouts)) "$viable") of $viable viable mutants"
fi
# The listed equivalents among this run's mutants, and how they came out.
listed() { if [[ -s "$out/$1.txt" ]]; then grep -cxF -f <(printf '%s\n' "${equivalent[@]}") "$out/$1.txt" || true; else echo 0; fi; }
eq_missed=$(listed missed)
eq_caught=$(($(listed caught) + $(listed timeout)))
if [[ $((eq_missed + eq_caught)) -gt 0 ]]; then
    rest=$((viable - eq_missed - eq_caught))
    echo "  without the $((eq_missed + eq_caught)) listed equivalent mutants in this run:"
    if [[ $rest -gt 0 ]]; then
        echo "            $(percent $((caught + timeouts - eq_caught)) "$rest") of $rest"
    fi
    if [[ $eq_caught -gt 0 ]]; then
        echo "  WARNING: $eq_caught listed as equivalent were caught: the argument for them is wrong"
    fi
fi
echo
echo "per file (caught+timeouts / viable):"
for file in $(cat "$out"/{caught,missed,timeout}.txt 2>/dev/null | cut -d: -f1 | sort -u); do
    in_file() { if [[ -s "$out/$1.txt" ]]; then grep -c "^$file:" "$out/$1.txt" || true; else echo 0; fi; }
    c=$(($(in_file caught) + $(in_file timeout)))
    m=$(in_file missed)
    echo "  $file: $c / $((c + m)) ($(percent "$c" $((c + m))))"
done
if [[ $missed -gt 0 ]]; then
    echo
    echo "missed mutants (the checks passed with these changes; = marks a listed equivalent):"
    while IFS= read -r name; do
        mark=" "
        for e in "${equivalent[@]}"; do [[ $name == "$e" ]] && mark="="; done
        echo " $mark $name"
    done <"$out/missed.txt"
fi
echo
echo "details: $details/ (outcomes.json, and a log per mutant); the scored lists: $out/"
