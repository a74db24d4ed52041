"""Issue 12's six bars, NCA against the base colour, for every image of a run's metrics.csv.

    python3 docs/tools/issue_bars.py RUN [RUN ...]

The bars (BENCHMARKS.md, "All twelve held-out faces, quality config, against the issue's six
bars"): the NCA's swd_L and style below the base colour's; its pore anisotropy within 0.1 of
the reference image's (`aniso_ref`); its orient and ring_ncc not more than 0.03 below the
base colour's; its dE_mean not more than 1 above. Every "bars" count of BENCHMARKS.md since
the thirty-third session comes from this script; earlier counts used the same rules.
Standard library only.
"""
import csv
import sys

ORIENT_SLACK = 0.03
RING_SLACK = 0.03
DE_SLACK = 1.0
ANISO_TOLERANCE = 0.1


def bars(nca, base):
    """The six pass/fail values of one image, in the order of the printed columns."""
    v = lambda row, key: float(row[key])
    return [
        v(nca, "swd_L") < v(base, "swd_L"),
        v(nca, "style") < v(base, "style"),
        abs(v(nca, "aniso") - v(nca, "aniso_ref")) <= ANISO_TOLERANCE,
        v(nca, "orient") >= v(base, "orient") - ORIENT_SLACK,
        v(nca, "ring_ncc") >= v(base, "ring_ncc") - RING_SLACK,
        v(nca, "dE_mean") <= v(base, "dE_mean") + DE_SLACK,
    ]


def report(run):
    with open(f"{run}/metrics.csv", newline="") as f:
        rows = {(r["method"], r["image"]): r for r in csv.DictReader(f)}
    print(f"{run}\n  image       swd_L style aniso orient ring dE  bars  (NCA / base colour)")
    total = 0
    for (method, image), nca in rows.items():
        base = rows.get(("base colour", image))
        if method != "nca" or base is None:
            continue
        passed = bars(nca, base)
        total += sum(passed)
        marks = "  ".join("yes" if p else "no " for p in passed)
        figures = ", ".join(
            f"{k} {float(nca[k]):.4g}/{float(base[k]):.4g}"
            for k in ("ring_ncc", "orient", "swd_L", "dE_mean", "style")
        )
        print(f"  {image:10s} {marks}  {sum(passed)}   {figures}, aniso {float(nca['aniso']):.2f} "
              f"(ref {float(nca['aniso_ref']):.2f})")
    print(f"  total {total}")


if __name__ == "__main__":
    if len(sys.argv) < 2:
        sys.exit(__doc__)
    for run in sys.argv[1:]:
        report(run)
