"""The predicted road against the measured one on rational clamped faces (issue 23, item 5).

Run:  python benchmarks/rational_borders.py [--faces 40] [--start 0] [--extension 3] [--truth]

Per face of ``cadartifact/testing/rational_faces.py`` (degrees 2-4, 6-14 points per direction, weights varying 10-45
%, a
smooth shape plus a small ripple): the predicted road's total ripple peak over the measured road's, along the
normal (the gated number), and each band's ratio; then the median, range and share within 10 %.
``--extension N`` gives the measured road a continuation period of N times the face (3 is the road as it
stands). ``--truth`` also draws each face 12 spans longer at every border and cuts it back
(``rational_faces.cut``: the same surface there, a clamped face of its own, of the face's size and degrees) and
divides both roads' peaks on the cut face by the longer face's measured ripple over the region it covers (a
border-free truth where the true ripple is large; where it is tiny the longer face's own reading dominates it,
and the ratio says little: the summary keeps the faces whose truth is at least 0.2 of the largest).
"""

from __future__ import annotations

import argparse
import time

import numpy as np

from cadartifact.analysis import fields
from cadartifact.analysis.budget import budget
from cadartifact.testing.rational_faces import border_free_truth, rational_face

BANDS = ("x1", "x2", "diagonal", "lateral", "total")


def _truth(seed: int) -> tuple[float, float, float]:
    """A face cut from a longer one: its predicted and measured total ripple peaks and the longer face's measured
    one over the region the face covers (the truth)."""
    face, truth = border_free_truth(seed)
    pb, mb = (budget(face, method=m).stats["total"].peak for m in ("predicted", "measured"))
    return pb, mb, truth


def _summary(name: str, r: np.ndarray) -> str:
    return (f"{name}: median {np.median(r):.3f}, range {r.min():.3f}-{r.max():.3f}, "
            f"within 10 % {np.mean(np.abs(r - 1.0) <= 0.10):.0%} of {len(r)}")


def main(argv=None) -> int:
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--faces", type=int, default=40)
    ap.add_argument("--start", type=int, default=0)
    ap.add_argument("--extension", type=int, default=fields.MEASURED_EXTENSION)
    ap.add_argument("--truth", action="store_true")
    args = ap.parse_args(argv)
    fields.MEASURED_EXTENSION = args.extension
    t0, rows, truth = time.perf_counter(), [], []
    for seed in range(args.start, args.start + args.faces):
        net = rational_face(seed)
        pb, mb = budget(net, method="predicted"), budget(net, method="measured")
        r = {k: pb.stats[k].peak / mb.stats[k].peak if mb.stats[k].peak > 0 else float("nan") for k in BANDS}
        rows.append(r)
        line = (f"face {seed:3d} {net.shape[0]:2d}x{net.shape[1]:<2d} degrees {net.degrees} measured "
                f"{mb.stats['total'].peak:.3e} mm  predicted/measured " + " ".join(f"{k} {r[k]:.3f}" for k in BANDS))
        if args.truth:
            fields.MEASURED_EXTENSION = 3
            cp, cm, t = _truth(seed)
            fields.MEASURED_EXTENSION = args.extension
            truth.append((cp / t, cm / t, t))
            line += f"  cut from a longer face: truth {t:.2e}, predicted {cp / t:.3f}, measured {cm / t:.3f}"
        print(line, flush=True)
    print(f"measured road's continuation period: {args.extension}x the face")
    for k in BANDS:
        vals = np.array([r[k] for r in rows])
        print(_summary(f"predicted/measured {k}", vals[np.isfinite(vals)]))
    if truth:
        tr = np.array(truth)
        big = tr[:, 2] >= 0.2 * tr[:, 2].max()
        print(_summary("predicted/truth (faces whose true ripple is at least 0.2 of the largest)", tr[big, 0]))
        print(_summary("measured/truth (the same faces)", tr[big, 1]))
    print(f"{time.perf_counter() - t0:.0f} s")
    return 0


if __name__ == "__main__":
    raise SystemExit(main())
