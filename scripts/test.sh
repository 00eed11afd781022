#!/usr/bin/env bash
# The whole test suite, from a fresh clone: installs what the tests need,
# then runs every test in debug, the pinned images again in release (the
# pixels must not depend on the build profile), and compiles the benchmarks.
# The optional Embree backend is always built and tested here, so that its
# cross-check of every chapter runs in CI (set-up: docs/embree.md).
set -euo pipefail
cd "$(dirname "$0")/.."

bash scripts/setup-embree.sh
cargo test --all-targets --features embree
# The default build needs no Embree, and says how to get it.
cargo test --test cli
cargo test --doc
# The lessons are the crate docs: they must build with no broken link.
RUSTDOCFLAGS="-D warnings" cargo doc --no-deps --features embree
cargo test --release --test snapshots --test determinism
cargo bench --no-run
