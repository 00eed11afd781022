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
#   `--re ch02_sphere` for one chapter or `--re rescaled_roots` for one
#   function (the regex is matched against the whole mutant name, file and
#   function included), or `--jobs 2`. (`--file` adds files to the chapter
#   glob below rather than narrowing it.)
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
    --exclude-re 'sphere_roots' \
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
# correct f32 formula. They stay in the run and in the first score; the
# second score leaves them out. docs/course.md ("Mutation score") gives the
# argument for each. The names carry the answer key's line numbers: if a
# chapter file changes, re-derive the list (the script says how many of
# them it found among the mutants it ran).
equivalent=(
    # ch01: `!(|denominator| > bound)` with >=: differs only where the
    # computed denominator equals its own rounding bound, parallel as far as
    # f32 can tell; the hit it then reports lies on the plane within the
    # checks' tolerance (or is infinite and rejected when both are 0).
    'src/chapters/ch01_plane.rs:33:28: replace > with >= in intersect_plane'
    # ch02, which path solves: the fast path and the rescaled one compute the
    # same roots (scaling by powers of two is exact) wherever both are free
    # of overflow; the rescaled one also rejects a miss by its own measure
    # of the line's distance, which differs from solve's only within
    # rounding of tangency. These send all input to the rescaled path
    # (==), or the exact boundary values (2^-60, 2^60) to the fast one
    # (>=, <=), which has margin there.
    'src/chapters/ch02_sphere.rs:38:27: replace > with == in roots_unless_behind'
    'src/chapters/ch02_sphere.rs:38:27: replace > with >= in roots_unless_behind'
    'src/chapters/ch02_sphere.rs:38:50: replace < with == in roots_unless_behind'
    'src/chapters/ch02_sphere.rs:38:50: replace < with <= in roots_unless_behind'
    'src/chapters/ch02_sphere.rs:39:30: replace < with == in roots_unless_behind'
    'src/chapters/ch02_sphere.rs:39:30: replace < with <= in roots_unless_behind'
    # ch02, the behind-the-origin shortcut (c > 0 && h > 0 gives None):
    # dropping it changes no answer, and extending it to c == 0 or h == 0
    # changes one only for an origin within rounding of the surface on a
    # ray within rounding of tangent to it.
    'src/chapters/ch02_sphere.rs:47:29: replace > with == in roots_unless_behind'
    'src/chapters/ch02_sphere.rs:47:29: replace > with >= in roots_unless_behind'
    'src/chapters/ch02_sphere.rs:47:40: replace > with == in roots_unless_behind'
    'src/chapters/ch02_sphere.rs:47:40: replace > with >= in roots_unless_behind'
    # ch02, choose_root's comparisons with a root's error bound, at equality:
    # a root exactly its bound beyond (or short of) t_min is beyond (short
    # of) it in exact arithmetic too, so taking or skipping the f64 solve
    # there, or accepting the far root, returns the same root within
    # rounding, or the same None.
    'src/chapters/ch02_sphere.rs:157:26: replace > with >= in choose_root'
    'src/chapters/ch02_sphere.rs:160:26: replace > with >= in choose_root'
    'src/chapters/ch02_sphere.rs:169:22: replace > with >= in choose_root'
    # ch02, the f64 near root of the band case rounded onto t_max itself:
    # the exact root is within rounding of t_max, either answer is right.
    'src/chapters/ch02_sphere.rs:165:23: replace < with <= in choose_root'
    # ch02, roots_f64's far root `mid + half`: its one caller, choose_root,
    # keeps only the near root (`let (exact_near, _) = roots_f64(..)`).
    'src/chapters/ch02_sphere.rs:222:46: replace + with - in roots_f64'
    'src/chapters/ch02_sphere.rs:222:46: replace + with * in roots_f64'
    # ch08, refract's eta = 1 shortcut, which returns a direction already
    # unit (squared length within 4 eps of 1) as it is: with + it never
    # applies and the direction is normalised again, which moves a unit
    # vector by a rounding or two, far within the checks' tolerance.
    'src/chapters/ch08_refraction.rs:41:55: replace - with + in refract'
    # ch08, cos i exactly 0 (the ray runs along the surface): which side
    # the normal is turned to, and so which side the ray bends into, is the
    # limit from either side; the exact answer is at the decision.
    'src/chapters/ch08_refraction.rs:45:22: replace < with <= in refract'
    # ch08, sin^2 t exactly 1 (exactly the critical angle) gives None
    # rather than the skimming ray (>=, ==); with ==, sin^2 t > 1 gives
    # cos t = sqrt(negative) = NaN, and unit_vector turns the NaN vector into
    # None: the same answer.
    'src/chapters/ch08_refraction.rs:55:25: replace > with == in refract'
    'src/chapters/ch08_refraction.rs:55:25: replace > with >= in refract'
    # ch08 and ch09, entering when d.n is exactly 0: a ray tangent to the
    # surface at the hit, where entering and leaving are both right.
    'src/chapters/ch08_refraction.rs:99:45: replace < with <= in shade_glass'
    'src/chapters/ch09_glass.rs:154:60: replace < with <= in crossing'
    # ch09, schlick's `n1 < n2` with <=: equal indices returned 0.0 just
    # before, so no input reaches the comparison with n1 == n2.
    'src/chapters/ch09_glass.rs:99:19: replace < with <= in schlick'
    # ch10, the swap of x and y when dir[z] < 0 (==, >, <=): without it (or
    # with it the other way) u, v and w are all exactly negated (the same
    # products, subtracted the other way round), the inside test accepts
    # both signs, and t = (u az + v bz + w cz) / (u + v + w) is unchanged:
    # the swap fixes only the winding's sign, which intersect_triangle does
    # not return.
    'src/chapters/ch10_triangles.rs:37:15: replace < with == in intersect_triangle'
    'src/chapters/ch10_triangles.rs:37:15: replace < with > in intersect_triangle'
    'src/chapters/ch10_triangles.rs:37:15: replace < with <= in intersect_triangle'
    # ch10, when the f64 recomputation of u, v, w runs: rounded products
    # keep the sign of their difference (rounding is monotonic), so an f32
    # edge function is either of the right sign or 0. Recomputing more often
    # (!=) changes values by a rounding; recomputing less often (&&, or !=
    # elsewhere) keeps a 0 whose exact value is a few roundings of the
    # products either side: the ray is within rounding of that edge, and
    # the mutant counts it inside (a hit), never outside.
    'src/chapters/ch10_triangles.rs:60:10: replace == with != in intersect_triangle'
    'src/chapters/ch10_triangles.rs:60:17: replace || with && in intersect_triangle'
    'src/chapters/ch10_triangles.rs:60:22: replace == with != in intersect_triangle'
    'src/chapters/ch10_triangles.rs:60:29: replace || with && in intersect_triangle'
    'src/chapters/ch10_triangles.rs:60:34: replace == with != in intersect_triangle'
    # ch10, smooth_hit_point's side test with <=: the vertex normals' sum
    # exactly in the triangle's plane says neither side is out; turning them
    # or not are both answers to a question with none.
    'src/chapters/ch10_triangles.rs:200:45: replace < with <= in smooth_hit_point'
)

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
echo "details: $out/ (outcomes.json, and a log per mutant)"
