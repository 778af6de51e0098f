"""The ``surface`` reading's split at the borders, against a border-free truth (issue 22, item 1: not yet an U).

Run:  python benchmarks/surface_split_truth.py [--seed 2] [--cases 60] [--margin 12]

The ``surface`` reading splits the real surface into its smooth part and its ripple (the measured road,
:func:`cadartifact.analysis.fields.measured_fields`: a polynomial fit, a Hermite bridge past each open
border, an FFT). What is uncertain is the border continuation. The truth used here: a clamped uniform
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
``E`` beyond 1, 2, 4 spans from the border, the largest change of the reading under alternate splits (bridge
period 2x instead of 3x, polynomial degree - 1); then the coverage of candidate estimates ``U = k * bord``.
About 2 s per case (the long face is read too).
"""

from __future__ import annotations

import argparse
import time
from types import SimpleNamespace

import numpy as np

from cadartifact.analysis.fields import _bridged_bands, _from_lifted, intent_normals
from cadartifact.analysis.intent import design_intent
from cadartifact.analysis.measure import real_surface
from cadartifact.net import ControlNet, clamped_uniform_knots, greville
from cadartifact.testing.known_shapes import DIRECTIONS, shape_function
from cadartifact.theory.catalogue import bspline


def homogeneous(net) -> np.ndarray:
    w = np.ones(net.shape) if net.weights is None else np.asarray(net.weights, float)
    return np.concatenate([np.asarray(net.points, float) * w[..., None], w[..., None]], axis=-1)


def cut(net, spans) -> ControlNet:
    """The face ``spans[axis]`` knot spans shorter at each border of each direction, exactly (scipy's basis)."""
    from scipy.interpolate import BSpline

    mats, knots = [], []
    for axis in (0, 1):
        p, n, t = net.degrees[axis], net.shape[axis], np.asarray(net.knots[axis], float)
        lo, hi, c = t[p], t[n], spans[axis]
        h = (hi - lo) / (n - p)
        a, b = lo + c * h, hi - c * h
        s = np.linspace(a, b, 6 * n + 7)
        kept = t[(t > a + 1e-12) & (t < b - 1e-12)]
        new = np.concatenate([[a] * (p + 1), kept, [b] * (p + 1)])
        whole = BSpline.design_matrix(s, t, p).toarray()
        part = BSpline.design_matrix(s, new, p).toarray()
        mats.append(np.linalg.pinv(part) @ whole)
        knots.append(new)
    H = np.einsum("ia,abc,jb->ijc", mats[0], homogeneous(net), mats[1])
    w = H[..., 3]
    return ControlNet(points=H[..., :3] / w[..., None], degrees=net.degrees, knots=tuple(knots),
                      weights=w if net.weights is not None else None)


def split(net, extension=3, ddeg=0, levels=3):
    """The measured road's ripple (``total``, ``(a, b, 3)``) and the smooth part's normals of a face."""
    sch = bspline(*net.degrees)
    it = design_intent(net, sch, levels)
    real = real_surface(it, sch)
    wide = tuple(f.with_extension(extension) for f in it.frames)
    degs = tuple(d + ddeg for d in net.degrees)
    bands, smooth, _ = _bridged_bands(real, wide, SimpleNamespace(degrees=degs, reproduction_degree=max(degs)), False)
    if smooth.shape[-1] == 4:
        bands, smooth, _ = _from_lifted(bands, smooth, real)
    return bands["total"], intent_normals(smooth, it.frames[0].K)


def draw(rng, margin: int):
    """One face of the family cut from a longer one, and the longer face's own reading over it (the truth).

    Returns ``(face, truth, K, text, (p, q, nu, nv, rational))``."""
    p, q = (int(d) for d in rng.integers(2, 6, 2))
    nu, nv = (int(rng.integers(max(6, d + 2), 41)) for d in (p, q))
    f = float(rng.uniform(0.05, 0.45))
    dname = str(rng.choice(list(DIRECTIONS)))
    kind = str(rng.choice(("cosine", "sum", "bump", "polynomial")))
    rational = bool(rng.random() < 0.3)
    Lu, Lv = nu - p + 2 * margin, nv - q + 2 * margin
    NU, NV = Lu + p, Lv + q
    ku, kv = clamped_uniform_knots(NU, p), clamped_uniform_knots(NV, q)
    gu, gv = greville(ku, p, NU), greville(kv, q, NV)
    g = shape_function(kind, f, DIRECTIONS[dname], float(rng.uniform(0, 2 * np.pi)), (Lu, Lv), rng)
    P = np.zeros((NU, NV, 3))
    P[..., 0], P[..., 1] = 100 * gu[:, None], 80 * gv[None, :]
    P[..., 2] = g(gu[:, None] * Lu, gv[None, :] * Lv)
    W = None
    if rational:
        fa, fb, ph = rng.uniform(0.02, 0.15), rng.uniform(0.02, 0.15), rng.uniform(0, 6)
        W = np.exp(0.3 * np.cos(2 * np.pi * (fa * np.arange(NU)[:, None] + fb * np.arange(NV)[None, :]) + ph))
    whole = ControlNet(points=P, degrees=(p, q), knots=(ku, kv), weights=W)
    face = cut(whole, (margin, margin))
    K = 8
    R_whole, _ = split(whole)
    truth = R_whole[margin * K: margin * K + (nu - p) * K + 1, margin * K: margin * K + (nv - q) * K + 1]
    text = f"{kind} f={f:.2f} {dname} degrees=({p},{q}) net={nu}x{nv} rational={rational}"
    return face, truth, K, text, (p, q, nu, nv, rational)


def case(rng, margin: int) -> dict:
    face, truth, K, text, (p, q, nu, nv, rational) = draw(rng, margin)
    R, normal = split(face)
    along = lambda a: np.abs(np.sum(a * normal, axis=-1))  # noqa: E731
    err = along(R - truth)
    border = np.zeros(err.shape, bool)
    border[: K + 1] = border[-K - 1:] = True
    border[:, : K + 1] = border[:, -K - 1:] = True
    row = {"text": text, "rational": rational, "E": float(err.max()), "true": float(along(truth).max()),
           "read": float(along(R).max()), "bord": float(along(R)[border].max())}
    row["Epk"] = abs(row["read"] - row["true"])
    for d in (1, 2, 4):
        row[f"E>{d}"] = float(err[d * K:-d * K, d * K:-d * K].max()) if min(nu - p, nv - q) > 2 * d else float("nan")
    for name, kw in (("period 2x", {"extension": 2}), ("degree-1", {"ddeg": -1})):
        row[name] = float(along(split(face, **kw)[0] - R).max())
    return row


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
        print(f"{r['text']:62s} " + " ".join(f"{k}={r[k]:.1e}" for k in r if k not in ("text", "rational")),
              flush=True)
    for label, rational in (("non-rational", False), ("rational", True)):
        rs = [r for r in rows if r["rational"] == rational and r["true"] > 1e-5]
        if not rs:
            continue
        E, Epk, bord, true = (np.array([r[k] for r in rs]) for k in ("E", "Epk", "bord", "true"))
        alt = np.array([max(r["period 2x"], r["degree-1"]) for r in rs])
        print(f"{label}: {len(rs)} faces with ripple > 1e-5: E / true ripple median {np.median(E / true):.2f}, "
              f"95th {np.percentile(E / true, 95):.2f}; alternates' spread covers E in {np.mean(E <= alt):.2f}")
        for k in (1, 1.5, 2, 3):
            print(f"  U = {k} x border ripple covers E in {np.mean(E <= k * bord):.3f}, Epk in {np.mean(Epk <= k * bord):.3f}")
    print(f"{time.perf_counter() - start:.0f} s")
    return 0


if __name__ == "__main__":
    raise SystemExit(main())
