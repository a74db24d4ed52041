"""How dark and how pale the fine detail of face images gets: percentiles of the detail.

    python3 docs/tools/detail_tails.py IMAGE.png [IMAGE.png ...]

The detail is what `pore_blobs.py` uses: the luminance (0..255 here) minus its Gaussian blur
(sigma 8 px). Its low percentiles are the pores; its high ones are the pale flecks and glints.
BENCHMARKS.md ("Pale flecks") compares the NCA's faces with the photos' by the 99th
percentile (and the 1st, the pores): a texture whose pale tail lies above the photo's paints light streaks the
wood does not have. The last two columns say where the pale detail lies: the correlation
of the dark part (pores) and the pale part of the detail, each blurred with sigma 2 and 4
px. On a photo of a radial face it is negative (pores in bands, clean wood between); a
texture that pays for each dark dash with light beside it has it near zero or positive.
Needs numpy and Pillow.
"""
import sys

import numpy as np
from pore_blobs import blur, detail_image, luminance

PERCENTILES = (1, 5, 25, 50, 75, 95, 99)
COLOCATION_SIGMAS = (2.0, 4.0)


def tails(path):
    """Mean luminance, the detail's spread, its percentiles and the dark-pale correlations."""
    lum = 255.0 * luminance(path)
    detail = 255.0 * detail_image(path)
    dark, pale = np.clip(-detail, 0, None), np.clip(detail, 0, None)
    colocation = [
        np.corrcoef(blur(dark, s).ravel(), blur(pale, s).ravel())[0, 1] for s in COLOCATION_SIGMAS
    ]
    return lum.mean(), detail.std(), np.percentile(detail, PERCENTILES), colocation


if __name__ == "__main__":
    if len(sys.argv) < 2:
        sys.exit(__doc__)
    header = ["p%d" % p for p in PERCENTILES] + ["dark_pale_corr_s%g" % s for s in COLOCATION_SIGMAS]
    print("image  mean  detail_std  " + "  ".join(header))
    for path in sys.argv[1:]:
        mean, std, pct, colocation = tails(path)
        print(f"{path}  {mean:.1f}  {std:.1f}  " + "  ".join(f"{v:.1f}" for v in pct) + "  "
              + "  ".join(f"{c:.3f}" for c in colocation))
