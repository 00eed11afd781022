#!/usr/bin/env bash
# Make the browser build (web/, scripts/build-web.sh) possible on this machine.
#
# With rustup's wasm32-unknown-unknown target installed (`rustup target add
# wasm32-unknown-unknown`, the ordinary way on a machine with network), there
# is nothing to do. Without it (a machine that reaches only the package
# registries), this fetches Debian's rustc-web and the source of its standard
# library, unpacks them under <repo>/.wasm-toolchain without installing them,
# and the build compiles std for wasm from that source (-Zbuild-std).
#
# Writes <repo>/.wasm-toolchain/env.sh, which scripts/build-web.sh sources:
#   WASM_MODE=rustup | debian, and for debian the compiler to use.
# Idempotent: a second run only checks a stamp file.
# Exits 3 (and says why) when neither way is available here.
set -euo pipefail

# Debian 12's rustc-web, by the upstream version in its library's package name.
RUST_WEB_VERSION="1.96"
PACKAGES=(rustc-web libstd-rust-web-dev "libstd-rust-web-$RUST_WEB_VERSION" rust-web-src libllvm22)

REPO="$(cd "$(dirname "${BASH_SOURCE[0]}")/.." && pwd)"
CACHE="$REPO/.wasm-toolchain"
ROOT="$CACHE/root"
STAMP="$CACHE/.done"
log() { echo "setup-wasm: $*" >&2; }
unavailable() { log "$*"; exit 3; }

mkdir -p "$CACHE"
if rustup target list --installed 2>/dev/null | grep -qx wasm32-unknown-unknown; then
    echo "WASM_MODE=rustup" > "$CACHE/env.sh"
    log "rustup has wasm32-unknown-unknown: nothing to fetch"
    exit 0
fi
if [[ -f "$STAMP" && "$(cat "$STAMP")" == "debian $RUST_WEB_VERSION" && -x "$ROOT/usr/bin/rustc" ]]; then
    exit 0
fi
command -v apt-get >/dev/null || unavailable "no wasm32-unknown-unknown target in rustup and no apt-get: run \`rustup target add wasm32-unknown-unknown\`"
command -v dpkg >/dev/null || unavailable "no dpkg to unpack Debian's rustc-web"
if ! apt-cache show "libstd-rust-web-$RUST_WEB_VERSION" >/dev/null 2>&1; then
    if [[ $(id -u) -eq 0 ]]; then
        apt-get update -qq >&2 || true
    fi
    apt-cache show "libstd-rust-web-$RUST_WEB_VERSION" >/dev/null 2>&1 \
        || unavailable "this machine's package lists have no libstd-rust-web-$RUST_WEB_VERSION (Debian 12's rustc-web); run \`rustup target add wasm32-unknown-unknown\` or \`apt-get update\` as root"
fi

DEBS="$CACHE/debs"
rm -rf "$DEBS" "$ROOT.partial"
mkdir -p "$DEBS" "$ROOT.partial"
log "fetching ${PACKAGES[*]} (not installing them)"
(cd "$DEBS" && apt-get download -qq "${PACKAGES[@]}" >&2) \
    || unavailable "apt-get download ${PACKAGES[*]} failed"
for deb in "$DEBS"/*.deb; do
    dpkg -x "$deb" "$ROOT.partial"
done
version="$(LD_LIBRARY_PATH="$ROOT.partial/usr/lib/x86_64-linux-gnu" "$ROOT.partial/usr/bin/rustc" --version)" \
    || unavailable "Debian's rustc-web does not run here"
[[ -d "$ROOT.partial/usr/lib/rustlib/src/rust/library/std" ]] || unavailable "rust-web-src has no library/std"
rm -rf "$ROOT" "$DEBS"
mv "$ROOT.partial" "$ROOT"
echo "WASM_MODE=debian" > "$CACHE/env.sh"
echo "debian $RUST_WEB_VERSION" > "$STAMP"
log "ok: $version, the standard library built from source"
