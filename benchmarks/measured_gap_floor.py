"""A floor on the measured road's continuation gap: what it would change (issue 23 item 5; not applied).

Run:  python benchmarks/measured_gap_floor.py [--floors 0 30 60] [--truth-seeds 2 3 4] [--truth-cases 60]

The measured road continues a face past each open border over a gap of about twice the face (period 3x,
``fields.MEASURED_EXTENSION``). A floor of ``G`` spans on that gap (the predicted road's clamped continuation has
one of 30, ``clamped.MIN_GAP``) is tried by giving each open frame the smallest period multiple that reaches it.
Per floor, three families that do not use the split's own model:

- ``rational``: predicted over measured total ripple peak on ``cadartifact/testing/rational_faces.py`` (24 faces);
- ``truth``: ``benchmarks/surface_split_truth.py``'s border-free truth (faces cut from faces 12 spans longer):
  the largest pointwise difference ``E`` and the peak difference ``Epk`` over the true ripple peak;
- ``short``: ``tests/analysis/test_short_nets.py``'s smooth least-squares fits: ripple peak over the distance to the
  shape.

Figures (2026-12-04, defaults; about 5 min):

| floor | rational: pred/meas, within 10 % | short: ripple/d median, worst | truth non-rational (92): Epk/true
median, 95th | rational (53) |
|---|---|---|---|---|
| 0 (as it stands) | 0.49-1.58, 62 % | 1.35, 2.59 | 0.20, 0.78 | 0.44, 0.99 |
| 30 | 0.85-1.08, 75 % | 1.38, 2.78 | 0.20, 0.65 | 0.44, 0.99 |
| 60 | 0.87-1.06, 96 % | 1.37, 2.73 | 0.20, 0.61 | 0.44, 1.00 |

Not applied (docs/model.md, "Rational faces at clamped borders"): a small gain at the border-free truth against
moving every short face's numbers.
"""

from __future__ import annotations

import argparse
import dataclasses
import math
import time
from contextlib import contextmanager

import numpy as np

import cadartifact as ca
from cadartifact.analysis.frames import AxisFrame


@contextmanager
def gap_floor(spans: int):
    """Open frames given a period long enough for a gap of at least ``spans`` spans (0: the road as it stands)."""
    kept = AxisFrame.with_extension

    def with_extension(self, extension):
        if not self.periodic and spans > 0:
            extension = max(extension, math.ceil((self.spans + spans) / self.spans))
        return dataclasses.replace(self, extension=extension)

    AxisFrame.with_extension = with_extension
    try:
        yield
    finally:
        AxisFrame.with_extension = kept


def rational() -> str:
    from cadartifact.testing.rational_faces import rational_face

    r = []
    for seed in range(24):
        net = rational_face(seed)
        r.append(ca.budget(net, method="predicted").stats["total"].peak
                 / ca.budget(net, method="measured").stats["total"].peak)
    r = np.array(r)
    return f"predicted/measured median {np.median(r):.3f}, {r.min():.2f}-{r.max():.2f}, within 10 % {np.mean(abs(r - 1) <= 0.1):.0%}"


def truth(seeds, cases) -> str:
    import surface_split_truth as T  # benchmarks/surface_split_truth.py, beside this script

    rows = []
    for seed in seeds:
        rng = np.random.default_rng(seed)
        rows += [T.case(rng, 12) for _ in range(cases)]
    out = []
    for label, rat in (("non-rational", False), ("rational", True)):
        rs = [r for r in rows if r["rational"] == rat and r["true"] > 1e-5]
        E, Epk, tr = (np.array([r[k] for r in rs]) for k in ("E", "Epk", "true"))
        out.append(f"{label} ({len(rs)}): E/true median {np.median(E / tr):.2f} 95th {np.percentile(E / tr, 95):.2f}, "
                   f"Epk/true median {np.median(Epk / tr):.2f} 95th {np.percentile(Epk / tr, 95):.2f}")
    return "; ".join(out)


def short() -> str:
    import short_nets_tradeoff as B  # benchmarks/short_nets_tradeoff.py, beside this script

    from cadartifact.testing.short_fits import distance_to_shape

    r = np.array([ca.budget(net).stats["total"].peak / distance_to_shape(net, distance)
                  for seed in (11, 12, 13) for net, _, distance, _ in B.faces(seed, 25)])
    return f"ripple/d median {np.median(r):.2f}, worst {r.max():.2f}, within 1.3 {np.mean(r <= 1.3):.0%}"


def main(argv=None) -> int:
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--floors", type=int, nargs="+", default=[0, 30, 60])
    ap.add_argument("--truth-seeds", type=int, nargs="+", default=[2, 3, 4])
    ap.add_argument("--truth-cases", type=int, default=60)
    args = ap.parse_args(argv)
    for floor in args.floors:
        t0 = time.perf_counter()
        with gap_floor(floor):
            print(f"gap floor {floor}: rational: {rational()}", flush=True)
            print(f"gap floor {floor}: short: {short()}", flush=True)
            print(f"gap floor {floor}: truth: {truth(args.truth_seeds, args.truth_cases)}", flush=True)
        print(f"  {time.perf_counter() - t0:.0f} s", flush=True)
    return 0


if __name__ == "__main__":
    raise SystemExit(main())
