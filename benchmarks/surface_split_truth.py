"""The ``surface`` reading's split at the borders, against a border-free truth (issue 22, item 1: not yet an U).

Run:  python benchmarks/surface_split_truth.py [--seed 2] [--cases 60] [--margin 12] [--rational-split cartesian]

The ``surface`` reading splits the real surface into its smooth part and its ripple (the measured road,
:func:`cadartifact.analysis.fields.measured_fields`: a polynomial fit, a Hermite bridge past each open
border, an FFT; a rational face in homogeneous coordinates, each band projected to first order, or with
``--rational-split cartesian`` as it stands). What is uncertain is the border continuation. The family and
the truth (cadartifact/testing/border_free.py): a clamped uniform
B-spline face (the "long" face) ``margin`` spans longer at each border than the face under test, whose control
points sample a known shape at their Greville abscissae (cadartifact/testing/known_shapes.py: cosines, sums of cosines,
bumps, polynomials, 0.05-0.45 cycles per point in four directions, random phases; degrees 2-5, nets of 6-40;
30 % of the faces rational, weights ``exp(0.3 cos(...))`` at 0.02-0.15 cycles per point). The face under test
is the long face cut at knots ``margin`` spans in from every border, computed exactly by scipy (least squares
of the homogeneous surface on its own clamped knots: the same surface, a clamped face with its own end
points). The long face's ripple on the cut region, where no border is within ``margin`` spans, is the
truth; the cut face's own reading is compared with it on the same fine grid (analysis coordinates are affine
in the parameter, so the grids coincide), along the cut face's normal (the gated component).

Printed per case: ``E`` (largest pointwise difference), ``Epk`` (difference of the peaks, what a decision
reads), the true ripple peak, the cut face's reading, the reading within one span of a border (``bord``),
``E`` beyond 1, 2, 4 spans from the border (``E>2 / E`` is the reading's locality), the largest change of the
reading under alternate splits (bridge period 2x instead of 3x, polynomial degree - 1); then the coverage of
candidate estimates ``U = k * bord``.
About 2 s per case (the long face is read too).
"""

from __future__ import annotations

import argparse
import time

import numpy as np

from cadartifact.testing.border_free import compare, long_face, split, truth_over

#: How rational faces are split (``fields.split_coordinates``): None (the road's own), "homogeneous", "cartesian".
RATIONAL_SPLIT = None


def draw(rng, margin: int):
    """One face of the family cut from a longer one, and the longer face's own reading over it (the truth).

    Returns ``(face, truth, K, text, (p, q, nu, nv, rational))``."""
    whole, face, info = long_face(rng, margin)
    (nu, nv), (p, q), K = info["shape"], info["degrees"], 8
    return face, truth_over(whole, face, margin, K), K, info["text"], (p, q, nu, nv, info["rational"])


def case(rng, margin: int) -> dict:
    whole, face, info = long_face(rng, margin)
    row = compare(whole, face, margin, rational_split=RATIONAL_SPLIT)
    err, R, normal = row.pop("err"), row.pop("R"), row.pop("normal")
    row.pop("truth")
    (nu, nv), (p, q) = info["shape"], info["degrees"]
    K = 8
    along = lambda a: np.abs(np.sum(a * normal, axis=-1))  # noqa: E731
    border = np.zeros(err.shape, bool)
    border[: K + 1] = border[-K - 1:] = True
    border[:, : K + 1] = border[:, -K - 1:] = True
    row = {"text": info["text"], "rational": info["rational"], **row, "bord": float(along(R)[border].max())}
    for name, kw in (("period 2x", {"extension": 2}), ("degree-1", {"ddeg": -1})):
        row[name] = float(along(split(face, rational_split=RATIONAL_SPLIT, **kw)[0] - R).max())
    return row


def main(argv=None) -> int:
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--seed", type=int, default=2)
    ap.add_argument("--cases", type=int, default=60)
    ap.add_argument("--margin", type=int, default=12)
    ap.add_argument("--rational-split", choices=("homogeneous", "cartesian"), default=None,
                    help="how rational faces are split (default: the measured road's own)")
    args = ap.parse_args(argv)
    global RATIONAL_SPLIT
    RATIONAL_SPLIT = args.rational_split
    rng = np.random.default_rng(args.seed)
    start, rows = time.perf_counter(), []
    for _ in range(args.cases):
        r = case(rng, args.margin)
        rows.append(r)
        print(f"{r['text']:62s} " + " ".join(f"{k}={r[k]:.1e}" for k in r if k not in ("text", "rational")),
              flush=True)
    for label, rational in (("non-rational", False), ("rational", True)):
        rs = [r for r in rows if r["rational"] == rational and r["true"] > 1e-5]
        if not rs:
            continue
        E, Epk, bord, true = (np.array([r[k] for r in rs]) for k in ("E", "Epk", "bord", "true"))
        alt = np.array([max(r["period 2x"], r["degree-1"]) for r in rs])
        far = np.array([r["E>2"] / r["E"] for r in rs if np.isfinite(r["E>2"])])
        print(f"{label}: {len(rs)} faces with ripple > 1e-5: E / true ripple median {np.median(E / true):.2f}, "
              f"95th {np.percentile(E / true, 95):.2f}; alternates' spread covers E in {np.mean(E <= alt):.2f}")
        print(f"  E beyond 2 spans / E ({len(far)} faces): median {np.median(far):.2f}, "
              f"75th {np.percentile(far, 75):.2f}, max {far.max():.2f}")
        for k in (1, 1.5, 2, 3):
            print(f"  U = {k} x border ripple covers E in {np.mean(E <= k * bord):.3f}, Epk in {np.mean(Epk <= k * bord):.3f}")
    print(f"{time.perf_counter() - start:.0f} s")
    return 0


if __name__ == "__main__":
    raise SystemExit(main())
