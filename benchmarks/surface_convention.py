"""The `surface` reading's border convention: its U against its latitude, and against a border-free truth.

Run:  python benchmarks/surface_convention.py [--seed 2] [--cases 60] [--margin 12]

The family of ``surface_split_truth.py`` (a clamped face cut exactly from one ``margin`` spans longer at every
border; known shapes, degrees 2-5, nets 6-40, a third rational). Per face, through
:func:`cadartifact.analysis.border_convention.variant_values`: the convention's value ``v`` (the face's peak
ripple along the normal), the spread ``D`` over the admissible periods (``T + 2``, ``T + 4``, each direction
alone and both), the grid term ``G`` and ``U = D + G``; then

* the grid's latitude: the same reading on a grid twice as fine (``levels`` 4), ``|v_16 - v|``;
* the bound the gate uses far from the tolerance: ``D / v`` (:data:`RELATIVE_BOUND`);
* the border-free truth (a property of the convention, not an error): the longer face's reading on the same
  region, ``|v - true|`` over the true peak and over ``U``.

Printed: one line per face, then the coverage and quantiles per non-rational / rational faces.
"""

from __future__ import annotations

import argparse
import time

import numpy as np

from surface_split_truth import draw, split
from cadartifact.analysis.border_convention import RELATIVE_BOUND, variant_values
from cadartifact.analysis.settings import RunSettings


def case(rng, margin: int) -> dict:
    face, truth, _, text, (*_, rational) = draw(rng, margin)
    _, normal = split(face)
    settings = RunSettings()
    v, both, alone, G = variant_values(face, settings)
    D = max([abs(x - v) for x in both] + [abs(x - v) for a in alone for x in a])
    v16 = variant_values(face, settings.replace(levels=4), pads=())[0]
    true = float(np.abs(np.sum(truth * normal, axis=-1)).max())
    return {"text": text, "rational": rational, "v": v, "D": D, "G": G, "U": D + G, "grid": abs(v16 - v), "true": true,
            "Epk": abs(v - true)}


def main(argv=None) -> int:
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--seed", type=int, default=2)
    ap.add_argument("--cases", type=int, default=60)
    ap.add_argument("--margin", type=int, default=12)
    args = ap.parse_args(argv)
    rng = np.random.default_rng(args.seed)
    start, rows = time.perf_counter(), []
    for _ in range(args.cases):
        r = case(rng, args.margin)
        rows.append(r)
        print(f"{r['text']:62s} " + " ".join(f"{k}={r[k]:.2e}" for k in r if k not in ("text", "rational")),
              flush=True)
    for label, rational in (("non-rational", False), ("rational", True)):
        rs = [r for r in rows if r["rational"] == rational and r["v"] > 1e-5]
        if not rs:
            continue
        v, D, U, grid, Epk, true = (np.array([r[k] for r in rs]) for k in ("v", "D", "U", "grid", "Epk", "true"))
        q = lambda a: f"median {np.median(a):.3f}, 95th {np.percentile(a, 95):.3f}, max {a.max():.3f}"  # noqa: E731
        print(f"{label}: {len(rs)} faces reading > 1e-5")
        print(f"  U / v: {q(U / v)}")
        print(f"  D / v: {q(D / v)}; within RELATIVE_BOUND {RELATIVE_BOUND}: {np.mean(D <= RELATIVE_BOUND * v):.3f}")
        print(f"  grid latitude (levels 4) within U: {np.mean(grid <= U):.3f}; |v16 - v| / U {q(grid / U)}")
        ok = true > 1e-5
        print(f"  border-free truth: |v - true| / true {q(Epk[ok] / true[ok])}; |v - true| / U {q(Epk / U)}; "
              f"within U {np.mean(Epk <= U):.3f}")
    print(f"{time.perf_counter() - start:.0f} s")
    return 0


if __name__ == "__main__":
    raise SystemExit(main())
