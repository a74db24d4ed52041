"""Ring-scale lightness profile of face images: how much darker the earlywood is than the
latewood, as a function of ring phase under a fitted field.

    cargo run --release --example face_growth -- RUN/fit/fit.toml G.npy
    python3 docs/tools/ring_profile.py G.npy SAMPLE_DIR RUN

G.npy holds G (years) on faces A..F ([6, 256, 256], `examples/face_growth.rs`); the fitted
field puts the rings at whole years, so frac(G) is the ring phase (0 at a ring boundary).
Per face, the mean grey level (0..255, Pillow's "L") of the pixels in each of 10 phase bins,
for the photo (SAMPLE_DIR/X_col.png), the base colour (RUN/fit/faces/X_base.png) and the NCA
(RUN/synth/faces/X.png). Printed: each image's profile amplitude (largest minus smallest bin
mean: how strongly the rings show at the scale of the rings, pores included), and the
correlation of the NCA's profile with the photo's. Used for BENCHMARKS ("Ring contrast of
the NCA against the photos"). Needs numpy and Pillow.
"""
import sys

import numpy as np
from PIL import Image

BINS = 10
FACES = "ABCDEF"


def grey(path):
    return np.asarray(Image.open(path).convert("L"), dtype=np.float64)


def profile(image, g):
    phase_bin = np.minimum((np.mod(g, 1.0) * BINS).astype(int), BINS - 1)
    return np.array([image[phase_bin == k].mean() for k in range(BINS)])


def amplitude(p):
    return p.max() - p.min()


def main():
    if len(sys.argv) != 4:
        sys.exit(__doc__)
    g_all = np.load(sys.argv[1])
    sample, run = sys.argv[2], sys.argv[3]
    print("face | photo | base colour | NCA | corr(NCA, photo)")
    for i, face in enumerate(FACES):
        g = g_all[i]
        photo = profile(grey(f"{sample}/{face}_col.png"), g)
        base = profile(grey(f"{run}/fit/faces/{face}_base.png"), g)
        nca = profile(grey(f"{run}/synth/faces/{face}.png"), g)
        corr = np.corrcoef(photo, nca)[0, 1]
        print(f"{face} | {amplitude(photo):.1f} | {amplitude(base):.1f} | {amplitude(nca):.1f} | {corr:.2f}")


if __name__ == "__main__":
    main()
