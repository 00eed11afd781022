#!/usr/bin/env bash
# Regenerates the pictures the lessons show (docs/images/) and prints the
# statistics the lessons quote. Run from anywhere; builds in release once.
set -euo pipefail
cd "$(dirname "$0")/.."
cargo build --release --quiet
raylab=target/release/raylab
mkdir -p docs/images

# Lesson 2: the textbook quadratic against the stable one, on a far small ball.
for formula in textbook stable; do
  "$raylab" render --scene docs/scenes/far-sphere.toml --chapter 5 \
    --sphere-formula "$formula" -o "docs/images/far-sphere-$formula.png"
done

# Lesson 4: shadow rays started exactly on the surface (acne) against the
# error-scaled offset.
"$raylab" render --chapter 5 --width 320 --height 240 --ray-offset fixed --epsilon 0 \
  -o docs/images/acne-epsilon-0.png --stats | grep -E "^chapter|self-shadowing"
"$raylab" render --chapter 5 --width 320 --height 240 \
  -o docs/images/acne-scaled.png --stats | grep -E "^chapter|self-shadowing"
