"""What ring_ncc a perfect texture would score on a real held-out face (issue 12's ring bar).

    python3 docs/tools/ring_floor.py PHOTO.png G.npy FACE BASE.png [XYLEM]

PHOTO is the held-out face's photo, G.npy the fit's growth field on the six faces
(`cargo run --release --example face_growth -- RUN/fit/fit.toml G.npy`), FACE its letter,
BASE the run's base colour of that face (RUN/fit/faces/X_base.png), XYLEM the binary
(default target/release/xylem).

Two stand-ins for "rings from the fit, texture as real as it gets", each scored with
`xylem compare PHOTO candidate` (its ring_ncc, the same code as the run's metrics):
- M: the photo's own mean colour in bins of 0.02 years of the fitted G, an oracle base colour
  that has seen the held-out photo (its per-ring darkness included);
- T = PHOTO - M: the photo's texture with the rings (as the fitted G places them) taken out,
  rolled along the image's columns by 32..192 px (CN03's side faces have their fibres along
  the columns), so its pores are real but independent of the photo's at every pixel;
- M + rolled T and BASE + rolled T: an exact sampler of this photo's texture on the oracle
  and on the fitted base colour.
Needs numpy and Pillow.
"""
import json
import os
import subprocess
import sys
import tempfile

import numpy as np
from PIL import Image

BIN_YEARS = 0.02
ROLLS = (32, 64, 96, 128, 160, 192)


def binned_mean(photo, g):
    """Per pixel: the mean colour of the photo over its bin of G."""
    bins = np.floor(g / BIN_YEARS).astype(int)
    bins -= bins.min()
    counts = np.maximum(np.bincount(bins.ravel()), 1)
    out = np.zeros_like(photo)
    for c in range(3):
        out[..., c] = (np.bincount(bins.ravel(), photo[..., c].ravel()) / counts)[bins]
    return out


def ring_ncc(xylem, reference, image, tmp):
    path = os.path.join(tmp, "candidate.png")
    Image.fromarray(np.clip(image, 0, 255).round().astype(np.uint8)).save(path)
    out = subprocess.run(
        [xylem, "compare", "-q", "--json", reference, path],
        check=True, capture_output=True, text=True,
    ).stdout
    data = json.loads(out)
    return data.get("metrics", data)["ring_ncc"]


def main():
    photo_path, g_path, face, base_path = sys.argv[1:5]
    xylem = sys.argv[5] if len(sys.argv) > 5 else "target/release/xylem"
    photo = np.asarray(Image.open(photo_path).convert("RGB"), dtype=float)
    base = np.asarray(Image.open(base_path).convert("RGB"), dtype=float)
    g = np.load(g_path)["ABCDEF".index(face)]
    oracle = binned_mean(photo, g)
    texture = photo - oracle
    with tempfile.TemporaryDirectory() as tmp:
        print(f"M (oracle base colour): ring_ncc {ring_ncc(xylem, photo_path, oracle, tmp):.3f}")
        print(f"BASE: ring_ncc {ring_ncc(xylem, photo_path, base, tmp):.3f}")
        for name, under in (("M", oracle), ("BASE", base)):
            scores = [
                ring_ncc(xylem, photo_path, under + np.roll(texture, r, axis=0), tmp)
                for r in ROLLS
            ]
            listed = " ".join(f"{s:.3f}" for s in scores)
            print(f"{name} + T rolled {ROLLS[0]}..{ROLLS[-1]} px: {listed} (mean {np.mean(scores):.3f})")


if __name__ == "__main__":
    main()
