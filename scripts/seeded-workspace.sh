#!/usr/bin/env bash
# One build of raylab for a class, measured: a new workspace's first build
# from nothing, against one whose target/ was copied from a workspace built
# before (the "seed"): cargo then compiles only the student's crate.
#
# Usage: scripts/seeded-workspace.sh [WORK_DIR]
#   WORK_DIR defaults to target/seeded-workspace (emptied first).
# Slow (the seed's build is a full one); not part of scripts/test.sh.
set -euo pipefail
root="$(cd "$(dirname "$0")/.." && pwd)"
work="${1:-$root/target/seeded-workspace}"
rm -rf "$work"
mkdir -p "$work"
raylab() { cargo run --quiet --release --manifest-path "$root/Cargo.toml" -- "$@"; }
seconds_since() { echo "$(date +%s.%N) - $1" | bc; }
unset CARGO_TARGET_DIR

raylab new "$work/seed" >/dev/null
start=$(date +%s.%N)
(cd "$work/seed" && cargo build --release --offline --quiet)
echo "the seed's first build (raylab included): $(seconds_since "$start") s (load $(cut -d' ' -f1 /proc/loadavg))"

raylab new "$work/student" >/dev/null
cp -a "$work/seed/target" "$work/student/target"
start=$(date +%s.%N)
(cd "$work/student" && cargo build --release --offline --quiet)
echo "a new workspace seeded with the seed's target/: $(seconds_since "$start") s (load $(cut -d' ' -f1 /proc/loadavg))"
echo "the seed's target/: $(du -sh "$work/seed/target" | cut -f1)"
