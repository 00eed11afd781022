#!/usr/bin/env bash
# Build the browser page: the chapters compiled to WebAssembly, the page's
# files (web/page/) and the lessons (rustdoc's pages of the chapters), in
# one folder any static web server can serve.
#
# Usage: scripts/build-web.sh [--crate DIR] [--out DIR] [--wasm-only]
#   --crate DIR  the cdylib crate to build (default: web/, raylab's own
#                chapters; `raylab web` in a student workspace passes one
#                that names the student's chapters)
#   --out DIR    where the page goes (default: target/web)
#   --wasm-only  compile the WebAssembly and stop: a later run puts the
#                page together (scripts/test.sh compiles it while the
#                native build runs, before the lessons are built)
# Then: python3 -m http.server -d target/web 8000, and open
# http://localhost:8000/ (a file:// page cannot start Web Workers).
#
# With rustup's wasm32-unknown-unknown target this is an ordinary cargo
# build; without it (no network but the package registries),
# scripts/setup-wasm.sh fetches Debian's rustc-web, and std is compiled from
# its source (-Zbuild-std). Exits 3, saying why, when neither is possible.
set -euo pipefail
REPO="$(cd "$(dirname "${BASH_SOURCE[0]}")/.." && pwd)"
CRATE="$REPO/web"
OUT="$REPO/target/web"
WASM_ONLY=0
while [[ $# -gt 0 ]]; do
    case "$1" in
        --crate) CRATE="$(cd "$2" && pwd)"; shift 2 ;;
        --out) mkdir -p "$2"; OUT="$(cd "$2" && pwd)"; shift 2 ;;
        --wasm-only) WASM_ONLY=1; shift ;;
        *) echo "build-web: unknown option '$1' (use --crate DIR, --out DIR or --wasm-only)" >&2; exit 2 ;;
    esac
done
log() { echo "build-web: $*" >&2; }

status=0
bash "$REPO/scripts/setup-wasm.sh" || status=$?
if [[ $status -ne 0 ]]; then
    log "no way to build for WebAssembly here (see above)"
    exit "$status"
fi
# shellcheck source=/dev/null
source "$REPO/.wasm-toolchain/env.sh"

# The wasm build has its own target folder: another compiler (Debian's),
# another standard library.
TARGET_DIR="${RAYLAB_WASM_TARGET_DIR:-$CRATE/target}"
build=(build --release --target wasm32-unknown-unknown --manifest-path "$CRATE/Cargo.toml" --target-dir "$TARGET_DIR")
start=$(date +%s)
if [[ $WASM_MODE == rustup ]]; then
    cargo "${build[@]}"
else
    # rustup's linker for wasm (rust-lld) and cargo, Debian's compiler,
    # which builds std from the source beside it. RUSTC_BOOTSTRAP unlocks
    # -Zbuild-std on a stable compiler, for this build only. std without
    # its features: unwinding (the page aborts on a panic) and backtraces'
    # symbols (object, gimli, addr2line), which a browser cannot use, are
    # crates to compile for nothing.
    toolchain="$REPO/.wasm-toolchain/root"
    lld="$(rustc --print sysroot)/lib/rustlib/x86_64-unknown-linux-gnu/bin/rust-lld"
    [[ -x "$lld" ]] || { log "rustup's toolchain has no rust-lld at $lld"; exit 3; }
    LD_LIBRARY_PATH="$toolchain/usr/lib/x86_64-linux-gnu${LD_LIBRARY_PATH:+:$LD_LIBRARY_PATH}" \
        RUSTC="$toolchain/usr/bin/rustc" RUSTC_BOOTSTRAP=1 \
        RUSTFLAGS="-C linker=$lld" \
        cargo "${build[@]}" -Zbuild-std=std,panic_abort -Zbuild-std-features=
fi
wasm="$(find "$TARGET_DIR/wasm32-unknown-unknown/release" -maxdepth 1 -name '*.wasm' -newer "$CRATE/Cargo.toml" -print -quit)"
[[ -n "$wasm" ]] || wasm="$(find "$TARGET_DIR/wasm32-unknown-unknown/release" -maxdepth 1 -name '*.wasm' -print -quit)"
[[ -n "$wasm" ]] || { log "cargo built no .wasm in $TARGET_DIR"; exit 1; }
log "WebAssembly built in $(( $(date +%s) - start )) s ($WASM_MODE): $(du -k "$wasm" | cut -f1) KB"
[[ $WASM_ONLY == 0 ]] || exit 0

# The lessons: rustdoc's pages of raylab's chapters (the crate docs): the
# ones RAYLAB_DOCS names if it is given (scripts/test.sh has just built
# them), else built where raylab's own builds go, unless that folder is not
# writable (a copy of raylab a class shares).
if [[ -n "${RAYLAB_DOCS:-}" && -f "$RAYLAB_DOCS/raylab/index.html" ]]; then
    DOCS="$RAYLAB_DOCS"
else
    DOC_TARGET="${CARGO_TARGET_DIR:-$REPO/target}"
    mkdir -p "$DOC_TARGET" 2>/dev/null || true
    [[ -w "$DOC_TARGET" ]] || DOC_TARGET="$TARGET_DIR/native"
    cargo doc --no-deps --manifest-path "$REPO/Cargo.toml" --target-dir "$DOC_TARGET" -q
    DOCS="$DOC_TARGET/doc"
fi

staging="$OUT.partial"
rm -rf "$staging"
mkdir -p "$staging"
cp "$REPO"/web/page/* "$staging/"
cp "$wasm" "$staging/raylab.wasm"
cp -r "$DOCS" "$staging/doc"
# No source pages on the page, even ones an older rustdoc run left in
# the docs folder: raylab's are the answer key.
rm -rf "$staging/doc/src"
bash "$REPO/scripts/check-docs-no-source.sh" "$staging/doc"
rm -rf "$OUT"
mv "$staging" "$OUT"
log "the page is in $OUT: serve it (python3 -m http.server -d $OUT 8000) and open http://localhost:8000/"
