"""How dark and how pale the fine detail of face images gets: percentiles of the detail.

    python3 docs/tools/detail_tails.py IMAGE.png [IMAGE.png ...]

The detail is what `pore_blobs.py` uses: the luminance (0..255 here) minus its Gaussian blur
(sigma 8 px). Its low percentiles are the pores; its high ones are the pale flecks and glints.
BENCHMARKS.md ("Pale flecks") compares the NCA's faces with the photos' by the 95th and
99th percentiles: a texture whose pale tail lies above the photo's paints light streaks the
wood does not have. Needs numpy and Pillow.
"""
import sys

from pore_blobs import DETAIL_SIGMA, blur, luminance

PERCENTILES = (1, 5, 25, 50, 75, 95, 99)


def tails(path):
    import numpy as np

    lum = 255.0 * luminance(path)
    detail = lum - blur(lum, DETAIL_SIGMA)
    return lum.mean(), detail.std(), np.percentile(detail, PERCENTILES)


if __name__ == "__main__":
    if len(sys.argv) < 2:
        sys.exit(__doc__)
    print("image  mean  detail_std  " + "  ".join(f"p{p}" for p in PERCENTILES))
    for path in sys.argv[1:]:
        mean, std, pct = tails(path)
        print(f"{path}  {mean:.1f}  {std:.1f}  " + "  ".join(f"{v:.1f}" for v in pct))
