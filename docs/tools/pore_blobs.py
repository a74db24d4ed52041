"""Pore shape statistics of face images: how wide, long, dark and many the dark blobs are.

    python3 docs/tools/pore_blobs.py IMAGE.png [IMAGE.png ...]

Used for docs/DESIGN.md ("Low band and rings-following grain", wider noise cells): the
luminance minus its Gaussian blur (sigma 8 px) is the fine detail; pixels below -1.5 of its
standard deviation are dark; their 4-connected components of 3 px or more are the blobs.
Per image: the dark share, the blob count, the mean area (px), the median length and width
(4 standard deviations along the blob's principal axes, px: a one-pixel-wide line has width
1.15) and the mean depth (how far below the local mean the blob lies, in luminance 0..1).
Needs numpy and Pillow.
"""
import sys

import numpy as np
from PIL import Image

DETAIL_SIGMA = 8.0
DARK_SD = 1.5
MIN_PIXELS = 3


def luminance(path):
    rgb = np.asarray(Image.open(path).convert("RGB"), dtype=np.float64) / 255.0
    return rgb @ np.array([0.2126, 0.7152, 0.0722])


def blur(image, sigma):
    radius = int(3 * sigma) + 1
    kernel = np.exp(-0.5 * (np.arange(-radius, radius + 1) / sigma) ** 2)
    kernel /= kernel.sum()
    padded = np.pad(image, radius, mode="reflect")
    rows = np.apply_along_axis(lambda v: np.convolve(v, kernel, "valid"), 0, padded)
    return np.apply_along_axis(lambda v: np.convolve(v, kernel, "valid"), 1, rows)


def components(mask):
    """4-connected components of a boolean image, as arrays of (row, col)."""
    h, w = mask.shape
    seen = np.zeros_like(mask, dtype=bool)
    found = []
    for r0, c0 in zip(*np.nonzero(mask)):
        if seen[r0, c0]:
            continue
        seen[r0, c0] = True
        stack, pixels = [(r0, c0)], []
        while stack:
            r, c = stack.pop()
            pixels.append((r, c))
            for nr, nc in ((r + 1, c), (r - 1, c), (r, c + 1), (r, c - 1)):
                if 0 <= nr < h and 0 <= nc < w and mask[nr, nc] and not seen[nr, nc]:
                    seen[nr, nc] = True
                    stack.append((nr, nc))
        found.append(np.array(pixels))
    return found


def detail_image(path):
    """The luminance (0..1) minus its Gaussian blur: the pore-scale detail of an image."""
    lum = luminance(path)
    return lum - blur(lum, DETAIL_SIGMA)


def blob_stats(path):
    detail = detail_image(path)
    dark = detail < -DARK_SD * detail.std()
    blobs = [b for b in components(dark) if len(b) >= MIN_PIXELS]
    lengths, widths, depths = [], [], []
    for b in blobs:
        centred = b - b.mean(axis=0)
        # + 1/12: the variance of a pixel's own extent, so a single row of pixels has width 1.15
        small, large = np.sort(np.linalg.eigvalsh(centred.T @ centred / len(b)))
        lengths.append(4 * np.sqrt(large + 1 / 12))
        widths.append(4 * np.sqrt(small + 1 / 12))
        depths.append(-detail[b[:, 0], b[:, 1]].mean())
    return {
        "dark": dark.mean(),
        "blobs": len(blobs),
        "area": float(np.mean([len(b) for b in blobs])) if blobs else 0.0,
        "length": float(np.median(lengths)) if blobs else 0.0,
        "width": float(np.median(widths)) if blobs else 0.0,
        "depth": float(np.mean(depths)) if blobs else 0.0,
    }


if __name__ == "__main__":
    for image_path in sys.argv[1:]:
        stats = blob_stats(image_path)
        print(image_path, " ".join(f"{k}={v:.3f}" for k, v in stats.items()))
