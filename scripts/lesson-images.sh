#!/usr/bin/env bash
# Regenerates the pictures the lessons show (docs/images/) and prints the
# statistics the lessons quote. Run from anywhere; builds in release once.
# RAYLAB=/path/to/raylab uses that binary instead of building one.
set -euo pipefail
cd "$(dirname "$0")/.."
if [[ -z "${RAYLAB:-}" ]]; then
  cargo build --release --quiet
  RAYLAB="${CARGO_TARGET_DIR:-target}/release/raylab"
fi
raylab="$RAYLAB"
mkdir -p docs/images
# --force: the committed images may predate raylab's marker in its PNGs, and
# `render` keeps a file it cannot tell it wrote.

# Lesson 2: the textbook quadratic against the stable one, on a small ball
# 2000 and 10 000 units away.
for scene in far-sphere-2000 far-sphere; do
  for formula in textbook stable; do
    "$raylab" render --scene "docs/scenes/$scene.toml" --chapter 5 \
      --sphere-formula "$formula" -o "docs/images/$scene-$formula.png" --force
  done
done

# Lesson 4: shadow rays started exactly on the surface (acne) against the
# error-scaled offset, with the textbook sphere test (the stable one has its
# own error bound, which hides most acne: the lesson says why both matter).
"$raylab" render --chapter 5 --width 320 --height 240 --sphere-formula textbook \
  --ray-offset fixed --epsilon 0 \
  -o docs/images/acne-epsilon-0.png --force --stats | grep -E "^chapter|self-shadowing"
"$raylab" render --chapter 5 --width 320 --height 240 --sphere-formula textbook \
  -o docs/images/acne-scaled.png --force --stats | grep -E "^chapter|self-shadowing"

# Lesson 10: the shadow terminator on a coarse smooth model lit from the
# side: rays leaving the flat triangles, then lifted by terminator_point.
for terminator in flat lifted; do
  "$raylab" render --scene docs/scenes/terminator.toml --chapter 10 \
    --terminator "$terminator" -o "docs/images/terminator-$terminator.png" --force
done
"$raylab" diff docs/images/terminator-flat.png docs/images/terminator-lifted.png | grep -E "^pixels over"
