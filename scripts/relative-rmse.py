#!/usr/bin/env python3
"""Relative RMSE of renders against a reference, in linear radiance.

usage: relative-rmse.py ENCODING REFERENCE IMAGE...

ENCODING says how the 8-bit codes of all the files were written:
  srgb    the sRGB curve, rounded (raylab's PNGs);
  gamma2  a square root, truncated to int(256 x) (the PPMs of Ray Tracing
          in One Weekend's books): decoded at the middle of each code's
          interval, ((code + 0.5) / 256)^2.

Prints, for each IMAGE, its mean, the reference's mean, the RMSE over every
channel of every pixel, and that RMSE divided by the reference's mean, so
that renderers with different encodings compare in the same unit, and the
share of the squared error held by the worst 1% of pixels (fireflies put
most of it there). Used by
docs/speed.md's "Path tracing" comparison. Needs numpy and Pillow
(Debian: python3-numpy python3-pil).
"""

import sys

import numpy as np
from PIL import Image


def decode_srgb(path):
    codes = np.asarray(Image.open(path).convert("RGB"), dtype=np.float64) / 255.0
    return np.where(codes <= 0.04045, codes / 12.92, ((codes + 0.055) / 1.055) ** 2.4)


def decode_gamma2(path):
    codes = np.asarray(Image.open(path).convert("RGB"), dtype=np.float64)
    return ((codes + 0.5) / 256.0) ** 2


def main(arguments):
    decoders = {"srgb": decode_srgb, "gamma2": decode_gamma2}
    if len(arguments) < 3 or arguments[0] not in decoders:
        sys.exit(__doc__.strip().splitlines()[2])
    decode = decoders[arguments[0]]
    reference = decode(arguments[1])
    for path in arguments[2:]:
        image = decode(path)
        if image.shape != reference.shape:
            sys.exit(f"{path}: {image.shape[1]}x{image.shape[0]}, the reference is "
                     f"{reference.shape[1]}x{reference.shape[0]}")
        squared = (image - reference) ** 2
        rmse = float(np.sqrt(np.mean(squared)))
        per_pixel = np.sort(squared.sum(axis=2).ravel())[::-1]
        worst = per_pixel[: max(1, per_pixel.size // 100)].sum() / max(per_pixel.sum(), 1e-300)
        print(f"{path}: mean {image.mean():.4f}, reference mean {reference.mean():.4f}, "
              f"RMSE {rmse:.5f}, relative {rmse / reference.mean():.3f}, "
              f"worst 1% of pixels {100 * worst:.0f}% of the squared error")


if __name__ == "__main__":
    main(sys.argv[1:])
