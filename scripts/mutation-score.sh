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
    # ch05, the clamp of the highlight's cosine at exactly 0 (<=): it sets
    # a cosine of 0 or -0 to +0, so the specular term can change only in
    # the sign of a zero, which no sum or comparison sees.
    'src/chapters/ch05_phong.rs:56:42: replace < with <= in phong_terms'
    # ch06, where reflect rescales huge directions: 2^63 + 2 (rounds to
    # 2^63) or 2^62 instead of 2^64, or 2^64 itself included (>=). Scaling
    # by a power of two is exact, so both formulas give the same bits
    # wherever neither overflows (the direct one cannot below 2^64, the
    # rescaled one cannot above 2^62) nor goes subnormal, which loses only
    # parts below 2^-64 in absolute terms, under 2^-126 of |d| > 2^62.
    'src/chapters/ch06_reflection.rs:35:43: replace * with + in reflect'
    'src/chapters/ch06_reflection.rs:35:43: replace * with / in reflect'
    'src/chapters/ch06_reflection.rs:36:30: replace > with >= in reflect'
    # ch07, the jittered clamp at 1 - 2^-23 or 1 - 2^-22 instead of
    # 1 - 2^-24: a sample beyond it moves by at most 3 * 2^-24 of a pixel,
    # still inside the pixel and its own cell (the last cell starts at
    # (k - 1) / k <= 63/64): a random point of the cell all the same.
    'src/chapters/ch07_antialiasing.rs:47:60: replace / with % in sample_offset'
    'src/chapters/ch07_antialiasing.rs:47:60: replace / with * in sample_offset'
    # ch07, whole_sqrt's loops: for every u32 n the f64 estimate is
    # already floor(sqrt(n)) (correctly rounded, it stays at least 2^-17
    # below k + 1; checked for all 2^32 values), so in the reference
    # neither loop body runs (82:14, 85:14), and a mutated first condition
    # that steps down (n = 1 for +, squares for == and >=) is stepped back
    # up by the second loop. / divides by zero only for n = 0, a count no
    # call has (no index below 0; scenes need samples >= 1). The second
    # condition as root * (root + 1) changes the root only for non-square
    # counts, which only random sampling takes, and it ignores the grid.
    'src/chapters/ch07_antialiasing.rs:81:16: replace * with + in whole_sqrt'
    'src/chapters/ch07_antialiasing.rs:81:16: replace * with / in whole_sqrt'
    'src/chapters/ch07_antialiasing.rs:81:23: replace > with == in whole_sqrt'
    'src/chapters/ch07_antialiasing.rs:81:23: replace > with >= in whole_sqrt'
    'src/chapters/ch07_antialiasing.rs:82:14: replace -= with += in whole_sqrt'
    'src/chapters/ch07_antialiasing.rs:82:14: replace -= with /= in whole_sqrt'
    'src/chapters/ch07_antialiasing.rs:84:17: replace + with * in whole_sqrt'
    'src/chapters/ch07_antialiasing.rs:84:30: replace + with * in whole_sqrt'
    'src/chapters/ch07_antialiasing.rs:85:14: replace += with -= in whole_sqrt'
    'src/chapters/ch07_antialiasing.rs:85:14: replace += with *= in whole_sqrt'
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
    # ch11, GAMMA_3 = 3u/(1 - 3u) off by O(u) of itself (3u, 3u(1 - 3u),
    # 3u/(1 + 3u), 3u/(1 - 6u), 3u/(1 - 12u)), or 2x or 4x (eps for u in
    # the numerator): the slack stays a few ulps of t, the box test stays
    # conservative, and only a ray within those ulps of a box's edge changes.
    'src/chapters/ch11_bvh.rs:17:46: replace / with %'
    'src/chapters/ch11_bvh.rs:17:46: replace / with *'
    'src/chapters/ch11_bvh.rs:17:53: replace / with %'
    'src/chapters/ch11_bvh.rs:17:53: replace / with *'
    'src/chapters/ch11_bvh.rs:17:60: replace - with +'
    'src/chapters/ch11_bvh.rs:17:82: replace / with %'
    'src/chapters/ch11_bvh.rs:17:82: replace / with *'
    # ch11, hit_box's folds at equality (near == entry, far == exit, t_min
    # == entry, t_max == exit) take the other of two equal values: the same
    # number but for the sign of a zero; a NaN fails > and >= alike. And
    # the slack's cap at slack == f32::MAX gives f32::MAX either way.
    'src/chapters/ch11_bvh.rs:77:25: replace > with >= in hit_box'
    'src/chapters/ch11_bvh.rs:78:23: replace < with <= in hit_box'
    'src/chapters/ch11_bvh.rs:84:18: replace < with <= in hit_box'
    'src/chapters/ch11_bvh.rs:88:26: replace > with >= in hit_box'
    'src/chapters/ch11_bvh.rs:89:25: replace < with <= in hit_box'
    # ch11, the middle cut's side test: with > the higher centroids go to
    # the first child (the same tree, children swapped), and with > or <= a
    # centroid exactly at the middle joins the lower ones: both sides stay
    # non-empty (the middle lies strictly between the extremes), the tree is
    # valid, the walks' answers do not depend on it, and the lesson fixes
    # neither convention.
    'src/chapters/ch11_bvh.rs:274:72: replace < with > in Cut::goes_left'
    'src/chapters/ch11_bvh.rs:274:72: replace < with <= in Cut::goes_left'
    # ch11, is_finite_box with ||: it differs only for a padded box with
    # one end finite and the other not. Shape boxes are NaN on both ends or
    # on neither, so that needs a finite box within 4 eps of f32::MAX, which
    # its padding carries past it; the checks (like chapter 3) count such a
    # box as finite, in the tree or out, and every answer stays chapter 3's.
    'src/chapters/ch11_bvh.rs:230:28: replace && with || in is_finite_box'
    # ch11, the widest axis with >=: of two equally wide axes the last,
    # not the first; a tie rule the lesson leaves open (any fixed one makes
    # the build deterministic).
    'src/chapters/ch11_bvh.rs:295:25: replace > with >= in choose_cut'
    # ch11, the SAH's skip of a cut with an empty side (&&): such a cut
    # costs TRAVERSAL_COST x area + the node's own area x count, more than
    # the leaf, so it is never returned, and it never beats a real cut that
    # beats the leaf.
    'src/chapters/ch11_bvh.rs:349:28: replace || with && in choose_cut'
    # ch11, TRAVERSAL_COST + node_area (+ instead of x): every cut's cost
    # grows by exactly 1 (1 + area for 1 x area), which changes the leaf-or-cut choice only where
    # the cheapest cut and the leaf are within one object test of each
    # other (an estimate's tie, not a rule the checks can ask for).
    'src/chapters/ch11_bvh.rs:352:35: replace * with + in choose_cut'
    # ch11, the SAH's ties (<=): of two cuts that cost the same, the last;
    # of a cut and a leaf that cost the same, the cut. Tie rules, valid
    # trees either way.
    'src/chapters/ch11_bvh.rs:356:50: replace < with <= in choose_cut'
    'src/chapters/ch11_bvh.rs:361:11: replace < with <= in choose_cut'
    # ch11, NodeStack::push with == or >: every entry goes to the Vec
    # (len == 64 is never reached, len > 64 never holds), which is then the
    # whole stack: the same order, slower.
    'src/chapters/ch11_bvh.rs:413:21: replace < with == in NodeStack::push'
    'src/chapters/ch11_bvh.rs:413:21: replace < with > in NodeStack::push'
    # ch11, the tie rule of Nearest::consider with <=: object == best.object
    # never happens, each object sits in one leaf (or in unbounded) and is
    # asked once per walk.
    'src/chapters/ch11_bvh.rs:462:73: replace < with <= in Nearest::consider'
    # ch11, which child the walk enters first (the guard always or never
    # true, or the entries compared with <=, == or >): the order of visits,
    # not the answer. The walk prunes by the best hit so far and never stops
    # at a first hit, so any order finds chapter 3's hit; a walk that always
    # goes left first is one of the course's accepted alternatives
    # (tests/chapter_11.rs).
    'src/chapters/ch11_bvh.rs:511:58: replace match guard right_entry < left_entry with false in nearest_hit_bvh'
    'src/chapters/ch11_bvh.rs:511:58: replace match guard right_entry < left_entry with true in nearest_hit_bvh'
    'src/chapters/ch11_bvh.rs:511:70: replace < with <= in nearest_hit_bvh'
    'src/chapters/ch11_bvh.rs:511:70: replace < with == in nearest_hit_bvh'
    'src/chapters/ch11_bvh.rs:511:70: replace < with > in nearest_hit_bvh'
)

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
    cat "${sources[@]}" 2>/dev/null | sort -u | { grep -Fxf "$out/current.txt" || true; } >"$out/$kind.txt"
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
