#!/usr/bin/env bash
# A synthetic class for `raylab grade --code`, and what judging it costs.
#
# Makes four workspaces once, each built in release: the answer key
# (`raylab new --solutions`), one in progress (the answer key's chapters 1
# to 6, the skeleton's after), the skeleton (nothing written), and a cheat
# (the answer key whose chapter 2 calls raylab's own `sphere.intersect` and
# whose chapter 7 prints a passing table and exits). Then CLASS_DIR gets
# STUDENTS workspaces, one of the four kinds in turn, each a copy of its
# kind's sources with its built binary linked into its own target/, and,
# unless --make-only, grades the class with /usr/bin/time and prints the
# wall time and the peak resident memory of the grader.
#
# What is measured is the judging: each student's build is stood in for by
# a `cargo` (given to raylab as $CARGO) that names the binary already in
# the workspace's target/, as cargo does when nothing changed. Building 500
# real workspaces takes hours and measures cargo, not raylab.
#
# Usage: scripts/synthetic-code-class.sh STUDENTS CLASS_DIR [--fresh SEED] [--make-only]
#   CLASS_DIR is emptied first; the kinds are built beside it, in
#   CLASS_DIR-kinds (kept between runs: the builds take minutes).
#   RAYLAB=path/to/raylab grades with another raylab binary (its kinds
#   must be built against the same source: give another CLASS_DIR).
set -euo pipefail
root="$(cd "$(dirname "$0")/.." && pwd)"
if [[ $# -lt 2 ]]; then
    echo "usage: $0 STUDENTS CLASS_DIR [--fresh SEED] [--make-only]" >&2
    exit 2
fi
students=$1
class=$(realpath -m "$2")
shift 2
fresh=()
make_only=
while [[ $# -gt 0 ]]; do
    case $1 in
    --fresh)
        fresh=(--fresh "$2")
        shift 2
        ;;
    --make-only)
        make_only=1
        shift
        ;;
    *)
        echo "unknown argument: $1" >&2
        exit 2
        ;;
    esac
done

if [[ -z ${RAYLAB:-} ]]; then
    cargo build --release --quiet --manifest-path "$root/Cargo.toml"
fi
raylab="${RAYLAB:-${CARGO_TARGET_DIR:-$root/target}/release/raylab}"
kinds="$class-kinds"
mkdir -p "$kinds"

# make_kind NAME [--solutions]: a workspace of the answer key or the
# skeleton, made once.
make_kind() {
    local name=$1
    shift
    if [[ ! -f "$kinds/$name/Cargo.toml" ]]; then
        rm -rf "$kinds/$name"
        "$raylab" new "$kinds/$name" "$@" >/dev/null
    fi
}
make_kind right --solutions
make_kind skeleton
if [[ ! -f "$kinds/progress/Cargo.toml" ]]; then
    make_kind progress
    for chapter in 01 02 03 04 05 06; do
        cp "$kinds/right/src/chapters/ch${chapter}_"*.rs "$kinds/progress/src/chapters/"
    done
fi
if [[ ! -f "$kinds/cheat/Cargo.toml" ]]; then
    make_kind cheat --solutions
    glue="$kinds/cheat/src/chapters/mod.rs"
    python3 - "$glue" <<'EOF'
import re, sys
path = sys.argv[1]
text = open(path).read()
# Each chapter's call in the glue, whatever its module is named.
for call, cheating in [
    ("intersect_sphere(sphere, ray, t_min, t_max)", "        sphere.intersect(ray, t_min, t_max)"),
    ("pixel_color(tracer, x, y)",
     "        {\n            println!(\"chapter  status       cases   robustness     image\");\n"
     "            println!(\"7        pass\");\n            std::process::exit(0)\n        }"),
]:
    honest = re.compile(r"        ch\d\d_\w+::" + re.escape(call))
    assert honest.search(text), call
    text = honest.sub(lambda _: cheating, text, count=1)
open(path, "w").write(text)
EOF
fi
# One target folder for the four: raylab and its dependencies build once.
for kind in right progress skeleton cheat; do
    (cd "$kinds/$kind" && CARGO_TARGET_DIR="$kinds/target" cargo build --release --offline --quiet)
done

# The stand-in for cargo: `build` names the one binary in the workspace's
# target/release, as cargo's JSON messages do; `run ... -- ARGS` runs it
# (what a raylab before the judge asked, for a measure side by side).
fake_cargo="$kinds/cargo"
cat >"$fake_cargo" <<'EOF'
#!/bin/sh
binary=$(find "$PWD/target/release" -maxdepth 1 -type f -perm -u+x | head -n 1)
if [ "$1" = run ]; then
    while [ $# -gt 0 ] && [ "$1" != -- ]; do shift; done
    shift
    exec "$binary" "$@"
fi
printf '{"reason":"compiler-artifact","executable":"%s"}\n' "$binary"
EOF
chmod +x "$fake_cargo"

rm -rf "$class"
mkdir -p "$class"
kind_names=(right progress skeleton cheat)
for index in $(seq 1 "$students"); do
    kind=${kind_names[$((index % 4))]}
    student="$class/$(printf 'student-%04d' "$index")"
    mkdir -p "$student/target/release"
    (cd "$kinds/$kind" && tar cf - --exclude=./target .) | (cd "$student" && tar xf -)
    ln "$kinds/target/release/$kind" "$student/target/release/"
done

if [[ -n $make_only ]]; then
    echo "made $students students in $class"
    exit 0
fi
# The students' target/ folders are this script's builds: a raylab that
# empties the target/ folders it did not leave must be told to keep them.
trust=()
if "$raylab" grade --help | grep -q -- --trust-targets; then
    trust=(--trust-targets)
fi
status=0
CARGO="$fake_cargo" /usr/bin/time -f '%e s wall, %M KB peak resident' \
    "$raylab" grade "$class" --code "${fresh[@]}" "${trust[@]}" >/dev/null 2>"$class.time" || status=$?
tail -1 "$class.time"
echo "grade exited $status (1: some students fail, as they should)"
cut -d, -f3 "$class/grades.csv" | sort | uniq -c
