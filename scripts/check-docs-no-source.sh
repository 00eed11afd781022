#!/usr/bin/env bash
# Fails, naming each page, when rustdoc's output would hand a student the
# answer key: a source page of raylab's chapters (src/raylab/chapters/...,
# the reference solutions, their checks and their tests) or a "Source"
# link on a page of the lessons (raylab/chapters/...). The lessons are the
# crate docs, which a student reads with `cargo doc --open` and the browser
# page ships; `#![doc(html_no_source)]` in src/lib.rs keeps the sources out.
#
# Usage: scripts/check-docs-no-source.sh [DOC_DIR]   (default: target/doc)
# Exits 1 on a leak, 2 when DOC_DIR holds no raylab docs.
set -euo pipefail
docs="${1:-${CARGO_TARGET_DIR:-target}/doc}"
if [[ ! -f "$docs/raylab/index.html" ]]; then
    echo "check-docs-no-source: no raylab docs in $docs: run cargo doc first" >&2
    exit 2
fi
leaks=()
# The chapters' pages first: they are the answer key.
if [[ -d "$docs/src/raylab" ]]; then
    while IFS= read -r page; do
        leaks+=("$page")
    done < <(find "$docs/src/raylab" -path '*/chapters/*' -name '*.html' | sort
        find "$docs/src/raylab" -name '*.html' -not -path '*/chapters/*' | sort)
fi
# rustdoc's link to an item's source is `<a class="src" href=...>Source</a>`:
# none may lead into raylab's source, and a lesson's page has none at all
# (elsewhere, those of the standard library's impls go to its own site).
while IFS= read -r page; do
    leaks+=("$page (a Source link)")
done < <({
    grep -rlE 'href="[^"]*src/raylab/' "$docs/raylab" || true
    grep -lE '<a class="src' "$docs/raylab/chapters/index.html" "$docs"/raylab/chapters/*/index.html || true
} | sort -u)
if [[ ${#leaks[@]} -gt 0 ]]; then
    echo "check-docs-no-source: FAILED: the docs in $docs show raylab's source" >&2
    echo "(the reference solutions are the answer key; keep #![doc(html_no_source)] in src/lib.rs):" >&2
    printf '  %s\n' "${leaks[@]:0:20}" >&2
    [[ ${#leaks[@]} -le 20 ]] || echo "  ... and $(( ${#leaks[@]} - 20 )) more" >&2
    exit 1
fi
echo "check-docs-no-source: no source pages and no Source links in $docs" >&2
