#!/usr/bin/env bash
# The whole test suite, from a fresh clone: installs what the tests need,
# then runs every test in debug, the pinned images again in release (the
# pixels must not depend on the build profile), and compiles the benchmarks.
set -euo pipefail
cd "$(dirname "$0")/.."

cargo test --all-targets
cargo test --doc
cargo test --release --test snapshots --test determinism
cargo bench --no-run
