"""Faces cut exactly from longer ones: the border-free truth of the ``surface`` reading.

The family of ``benchmarks/surface_split_truth.py`` and ``tests/analysis/test_local_rational_reading.py``. A
clamped uniform B-spline face (the "long" face) ``margin`` spans longer at every border than the face under test,
its control points sampling a known shape at their Greville abscissae (:mod:`cadartifact.testing.known_shapes`:
cosines, sums of cosines, bumps, polynomials, 0.05-0.45 cycles per point in four directions, random phases;
degrees 2-5, nets of 6-40; 30 % of the faces rational, weights ``exp(0.3 cos(...))`` at 0.02-0.15 cycles per
point). The face under test is the long face cut at knots ``margin`` spans in from every border (:func:`cut`: the
same surface, a clamped face with its own end points). The long face's reading on the cut region, where no
border is within ``margin`` spans, is the truth; the cut face's reading is compared with it on the same fine
grid (analysis coordinates are affine in the parameter, so the grids coincide), along the cut face's normal.
"""

from __future__ import annotations

from types import SimpleNamespace

import numpy as np

from cadartifact.net import ControlNet, clamped_uniform_knots, greville
from cadartifact.testing.known_shapes import DIRECTIONS, shape_function

__all__ = ["homogeneous", "cut", "long_face", "split", "truth_over", "compare", "unmoved_surface"]


def homogeneous(net) -> np.ndarray:
    """``(nu, nv, 4)``: the net's homogeneous points ``(w P, w)`` (``w = 1`` without weights)."""
    w = np.ones(net.shape) if net.weights is None else np.asarray(net.weights, float)
    return np.concatenate([np.asarray(net.points, float) * w[..., None], w[..., None]], axis=-1)


def cut(net, spans) -> ControlNet:
    """The face ``spans[axis]`` knot spans shorter at each border of each direction, exactly (scipy's basis:
    least squares of the homogeneous surface on the shorter clamped knots)."""
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


def long_face(rng, margin: int, rational: bool | None = None) -> tuple[ControlNet, ControlNet, dict]:
    """One draw of the family: ``(long face, the face cut from it, description)``.

    ``rational``: force the kind (the draw of the weights is made either way, so the shape stays the draw's).
    """
    p, q = (int(d) for d in rng.integers(2, 6, 2))
    nu, nv = (int(rng.integers(max(6, d + 2), 41)) for d in (p, q))
    f = float(rng.uniform(0.05, 0.45))
    dname = str(rng.choice(list(DIRECTIONS)))
    kind = str(rng.choice(("cosine", "sum", "bump", "polynomial")))
    drawn = bool(rng.random() < 0.3)
    rational = drawn if rational is None else rational
    Lu, Lv = nu - p + 2 * margin, nv - q + 2 * margin
    NU, NV = Lu + p, Lv + q
    ku, kv = clamped_uniform_knots(NU, p), clamped_uniform_knots(NV, q)
    gu, gv = greville(ku, p, NU), greville(kv, q, NV)
    g = shape_function(kind, f, DIRECTIONS[dname], float(rng.uniform(0, 2 * np.pi)), (Lu, Lv), rng)
    P = np.zeros((NU, NV, 3))
    P[..., 0], P[..., 1] = 100 * gu[:, None], 80 * gv[None, :]
    P[..., 2] = g(gu[:, None] * Lu, gv[None, :] * Lv)
    W = None
    if drawn or rational:
        fa, fb, ph = rng.uniform(0.02, 0.15), rng.uniform(0.02, 0.15), rng.uniform(0, 6)
        if rational:
            W = np.exp(0.3 * np.cos(2 * np.pi * (fa * np.arange(NU)[:, None] + fb * np.arange(NV)[None, :]) + ph))
    whole = ControlNet(points=P, degrees=(p, q), knots=(ku, kv), weights=W)
    info = {"text": f"{kind} f={f:.2f} {dname} degrees=({p},{q}) net={nu}x{nv} rational={rational}",
            "rational": rational, "kind": kind, "shape": (nu, nv), "degrees": (p, q)}
    return whole, cut(whole, (margin, margin)), info


def unmoved_surface(net, u: np.ndarray, v: np.ndarray, steps: int = 60) -> np.ndarray:
    """A rational face read where its weights have not moved it: ``(len(u), len(v), 3)``.

    The weights move a rational face along itself: the rational basis ``R`` applied to the Greville abscissae,
    ``(R xi_u, R xi_v)(s, t)``, is not ``(s, t)`` (for equal weights it is: linear precision). The surface is read
    at the ``(s, t)`` where that map gives the grid ``(u, v)`` (fixed-point steps ``(s, t) -= map - (u, v)``), so
    the weights' tangential motion, whose harmonics lie near half a cycle per span, is not split. A measurement
    candidate (dense bases: slow on long faces), not the road's.
    """
    from cadartifact.numerics.splines import basis_matrix

    (p, q), (nu, nv) = net.degrees, net.shape
    ku, kv = (np.asarray(k, float) for k in net.knots)
    W = np.ones(net.shape) if net.weights is None else np.asarray(net.weights, float)
    gu, gv = greville(ku, p, nu), greville(kv, q, nv)
    H = np.concatenate([homogeneous(net), (W * gu[:, None])[..., None], (W * gv[None, :])[..., None]], axis=-1)
    X, Y = np.meshgrid(u, v, indexing="ij")
    S, T = X.copy(), Y.copy()

    def at(S, T):
        Bu, Bv = basis_matrix(ku, p, S.ravel(), nu), basis_matrix(kv, q, T.ravel(), nv)
        return np.einsum("ki,ijc,kj->kc", Bu, H, Bv).reshape(S.shape + (6,))

    for _ in range(steps):
        E = at(S, T)
        du, dv = E[..., 4] / E[..., 3] - X, E[..., 5] / E[..., 3] - Y
        S, T = np.clip(S - du, u[0], u[-1]), np.clip(T - dv, v[0], v[-1])
        if max(np.abs(du).max(), np.abs(dv).max()) <= 1e-13:
            break
    E = at(S, T)
    return E[..., :3] / E[..., 3:4]


def split(net, extension: int = 3, ddeg: int = 0, levels: int = 3, rational_split: str | None = None):
    """The measured road's ripple (``total``, ``(a, b, 3)``) and the smooth part's normals of a face.

    ``extension``, ``ddeg``: alternate splits (bridge period, polynomial degree). ``rational_split``:
    ``"homogeneous"`` or ``"cartesian"`` (:func:`cadartifact.analysis.fields.split_coordinates`; default the
    road's own), or ``"unmoved"``: the Cartesian split of :func:`unmoved_surface` (a candidate).
    """
    from cadartifact.analysis.fields import _bridged_bands, _from_lifted, intent_normals, split_coordinates
    from cadartifact.analysis.intent import design_intent
    from cadartifact.analysis.measure import real_surface
    from cadartifact.theory.catalogue import bspline

    sch = bspline(*net.degrees)
    it = design_intent(net, sch, levels)
    if rational_split == "unmoved" and net.weights is not None:
        fu, fv = it.frames
        real = unmoved_surface(net, fu.param(fu.x), fv.param(fv.x))
    else:
        real = split_coordinates(real_surface(it, sch), it.frames, rational_split)
    wide = tuple(f.with_extension(extension) for f in it.frames)
    degs = tuple(d + ddeg for d in net.degrees)
    bands, smooth, _ = _bridged_bands(real, wide, SimpleNamespace(degrees=degs, reproduction_degree=max(degs)),
                                      False)
    if smooth.shape[-1] == 4:
        bands, smooth, _ = _from_lifted(bands, smooth, real)
    return bands["total"], intent_normals(smooth, it.frames[0].K)


def truth_over(whole, face, margin: int, K: int = 8, **options) -> np.ndarray:
    """The long face's ripple (:func:`split`) on the region ``face`` was cut from: ``(a, b, 3)`` on the cut
    face's fine grid (``K`` points per span). ``options`` go to :func:`split`."""
    (nu, nv), (p, q) = face.shape, face.degrees
    R_whole, _ = split(whole, **options)
    return R_whole[margin * K: margin * K + (nu - p) * K + 1, margin * K: margin * K + (nv - q) * K + 1]


def compare(whole, face, margin: int, K: int = 8, **options) -> dict:
    """The cut face's reading against the long face's on the cut region, along the cut face's normal.

    Returns ``E`` (largest pointwise difference), ``true`` (the long face's ripple peak there), ``read`` (the cut
    face's), ``Epk = |read - true|``, ``E>d`` (the largest difference ``d`` spans or more from every border, nan
    where the face is too short) for d = 1, 2, 4, and the fields ``err``, ``R``, ``truth``, ``normal``.
    ``options`` go to :func:`split`.
    """
    (nu, nv), (p, q) = face.shape, face.degrees
    truth = truth_over(whole, face, margin, K, **options)
    R, normal = split(face, **options)

    def along(a):
        return np.abs(np.sum(a * normal, axis=-1))

    err = along(R - truth)
    row = {"E": float(err.max()), "true": float(along(truth).max()), "read": float(along(R).max()),
           "err": err, "R": R, "truth": truth, "normal": normal}
    row["Epk"] = abs(row["read"] - row["true"])
    for d in (1, 2, 4):
        row[f"E>{d}"] = float(err[d * K:-d * K, d * K:-d * K].max()) if min(nu - p, nv - q) > 2 * d else float("nan")
    return row
