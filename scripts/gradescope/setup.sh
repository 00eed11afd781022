#!/usr/bin/env bash
# Gradescope's setup.sh: run once, as root, when Gradescope builds the
# autograder's image (Ubuntu). The autograder's zip holds this file,
# run_autograder and raylab's source in raylab/ (see docs/instructors.md,
# "Gradescope"). Installs Rust and bubblewrap, builds raylab, fetches the
# crates a workspace builds from (grading builds --offline), and builds a
# template workspace once, so that each submission only compiles its own
# chapters.
set -euo pipefail
source_dir=/autograder/source
export DEBIAN_FRONTEND=noninteractive
apt-get update -qq
apt-get install -y -qq --no-install-recommends \
    build-essential ca-certificates curl bubblewrap >/dev/null
if ! command -v cargo >/dev/null; then
    curl --proto '=https' --tlsv1.2 -sSf https://sh.rustup.rs \
        | sh -s -- -y --profile minimal
fi
export PATH="$HOME/.cargo/bin:$PATH"
cd "$source_dir/raylab"
cargo build --release --locked
cargo fetch --locked
install -m 755 target/release/raylab /usr/local/bin/raylab
# The template workspace: named as each submission's copy will be, so that
# its build of raylab is the one the submission's build reuses.
rm -rf /autograder/template
mkdir -p /autograder/template
raylab new /autograder/template/submission
(cd /autograder/template/submission && cargo build --release --offline)
