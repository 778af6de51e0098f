"""Clamped B-spline faces whose control points sample a known smooth shape at their Greville abscissae.

Shapes are functions of ``(X, Y)``, the face's parameters in spans (one unit per knot span, so
frequencies are in cycles per control point on the interior): cosines along u, along v, diagonal
and at 30 degrees with random phase, sums of cosines, and bumps. ``z`` carries the shape (amplitude
1 unless scaled); ``x``, ``y`` are linear in the parameters (so the normal is z).
"""

from __future__ import annotations

import numpy as np

from cadartifact.net import ControlNet, clamped_uniform_knots, greville

DIRECTIONS = {"u": 0.0, "v": np.pi / 2, "diagonal": np.pi / 4, "30deg": np.pi / 6}


def shape_function(kind: str, f: float, theta: float, phase: float, spans: tuple[int, int], rng=None):
    """A known shape ``g(X, Y)`` (spans units) of amplitude 1."""
    rng = rng or np.random.default_rng(0)
    c, s = np.cos(theta), np.sin(theta)
    if kind == "cosine":
        return lambda X, Y: np.cos(2 * np.pi * f * (c * X + s * Y) + phase)
    if kind == "sum":
        f2, p2 = f * rng.uniform(0.3, 0.7), rng.uniform(0, 2 * np.pi)
        return lambda X, Y: 0.6 * np.cos(2 * np.pi * f * (c * X + s * Y) + phase) + 0.4 * np.cos(
            2 * np.pi * f2 * (s * X - c * Y) + p2)
    if kind == "bump":  # a Gaussian ridge whose spectrum fades by f
        cx, cy = (rng.uniform(0.35, 0.65) * L for L in spans)
        w = 1.0 / (2.0 * f)
        return lambda X, Y: np.exp(-((c * (X - cx) + s * (Y - cy)) / w) ** 2)
    if kind == "polynomial":  # a random polynomial of degree 2-4 in the rotated coordinate, peak 1 on the face
        deg = int(rng.integers(2, 5))
        coef = rng.normal(size=deg + 1)
        Lx = abs(c) * spans[0] + abs(s) * spans[1] or 1.0
        t = np.linspace(-1, 1, 201)
        scale = float(np.abs(np.polynomial.legendre.legval(t, coef)).max()) or 1.0
        return lambda X, Y: np.polynomial.legendre.legval(2 * (c * X + s * Y) / Lx - 1, coef) / scale
    raise ValueError(kind)


def known_face(degrees, shape_n, g, size=(100.0, 80.0), amplitude=1.0):
    """The clamped face of ``shape_n`` points sampling ``amplitude * g`` at its Greville abscissae.

    Returns
    -------
    (net, truth) : (ControlNet, callable)
        ``truth(u, v)`` gives the known surface ``(len(u), len(v), 3)`` at parameters in ``[0, 1]``.
    """
    (p, q), (nu, nv) = degrees, shape_n
    ku, kv = clamped_uniform_knots(nu, p), clamped_uniform_knots(nv, q)
    gu, gv = greville(ku, p, nu), greville(kv, q, nv)
    Lu, Lv = nu - p, nv - q

    def truth(u, v):
        u, v = np.asarray(u, float), np.asarray(v, float)
        out = np.zeros((len(u), len(v), 3))
        out[..., 0] = size[0] * u[:, None]
        out[..., 1] = size[1] * v[None, :]
        out[..., 2] = amplitude * g(u[:, None] * Lu, v[None, :] * Lv)
        return out

    return ControlNet(points=truth(gu, gv), degrees=(p, q), knots=(ku, kv)), truth


def family(seed: int, count: int, *, fmax=0.35, nmin=14, nmax=40, kinds=("cosine", "sum", "bump")):
    """``count`` random known faces: (net, truth, description)."""
    rng = np.random.default_rng(seed)
    out = []
    for _ in range(count):
        p, q = (int(d) for d in rng.integers(2, 6, 2))
        nu, nv = (int(n) for n in rng.integers(nmin, nmax + 1, 2))
        f = float(rng.uniform(0.05, fmax))
        dname = str(rng.choice(list(DIRECTIONS)))
        kind = str(rng.choice(kinds))
        g = shape_function(kind, f, DIRECTIONS[dname], float(rng.uniform(0, 2 * np.pi)), (nu - p, nv - q), rng)
        net, truth = known_face((p, q), (nu, nv), g)
        out.append((net, truth, f"{kind} f={f:.3f} {dname} degrees=({p},{q}) net={nu}x{nv}"))
    return out


CALIBRATION_KINDS = ("cosine", "sum", "bump", "polynomial")


def calibration_family(seed: int, count: int, *, nmin=6, nmax=40, fmin=0.05, fmax=0.45, degrees=(1, 5),
                       tol_range=(0.002, 0.1)):
    """``count`` random known faces of issue 22's calibration: nets of ``nmin``-``nmax`` points per
    direction, degrees ``degrees`` (inclusive), content ``fmin``-``fmax`` cycles per point in any of
    four directions, random phases, cosines, sums of cosines, bumps and polynomials; a tolerance drawn
    log-uniformly in ``tol_range`` of the amplitude (1).

    Returns
    -------
    list of (net, truth, info)
        ``info``: ``{"kind", "f", "direction", "degrees", "shape", "tolerance", "text"}``.
    """
    rng = np.random.default_rng(seed)
    out = []
    for _ in range(count):
        p, q = (int(d) for d in rng.integers(degrees[0], degrees[1] + 1, 2))
        nu, nv = (int(rng.integers(max(nmin, d + 2), nmax + 1)) for d in (p, q))
        f = float(rng.uniform(fmin, fmax))
        dname = str(rng.choice(list(DIRECTIONS)))
        kind = str(rng.choice(CALIBRATION_KINDS))
        g = shape_function(kind, f, DIRECTIONS[dname], float(rng.uniform(0, 2 * np.pi)), (nu - p, nv - q), rng)
        net, truth = known_face((p, q), (nu, nv), g)
        t = float(np.exp(rng.uniform(np.log(tol_range[0]), np.log(tol_range[1]))))
        info = {"kind": kind, "f": f, "direction": dname, "degrees": (p, q), "shape": (nu, nv), "tolerance": t,
                "text": f"{kind} f={f:.3f} {dname} degrees=({p},{q}) net={nu}x{nv} t={t:.4g}"}
        out.append((net, truth, info))
    return out


def net_reading_family(seed: int, count: int, *, nets=(10, 28), degrees=(2, 3, 5), band=(0.1, 0.4),
                       directions=("u", "v", "diagonal"), kinds=("cosine", "sum", "bump"),
                       tolerances=(0.01, 0.05)):
    """``count`` random known faces of issue 39's ``net`` reading family: nets of ``nets`` points per
    direction (inclusive), degrees drawn from ``degrees``, content ``band`` cycles per point in one of
    ``directions``, random phases, shapes of ``kinds``, a tolerance drawn from ``tolerances`` (amplitude 1).
    Families held out of a calibration change one of these (other degrees, sizes, directions or kinds).

    Returns
    -------
    list of (net, truth, info)
        As :func:`calibration_family`.
    """
    rng = np.random.default_rng(seed)
    out = []
    for _ in range(count):
        p, q = (int(rng.choice(degrees)) for _ in range(2))
        nu, nv = (int(rng.integers(max(nets[0], d + 2), nets[1] + 1)) for d in (p, q))
        f = float(rng.uniform(*band))
        dname = str(rng.choice(list(directions)))
        kind = str(rng.choice(list(kinds)))
        g = shape_function(kind, f, DIRECTIONS[dname], float(rng.uniform(0, 2 * np.pi)), (nu - p, nv - q), rng)
        net, truth = known_face((p, q), (nu, nv), g)
        t = float(rng.choice(tolerances))
        info = {"kind": kind, "f": f, "direction": dname, "degrees": (p, q), "shape": (nu, nv), "tolerance": t,
                "text": f"{kind} f={f:.3f} {dname} degrees=({p},{q}) net={nu}x{nv} t={t:.4g}"}
        out.append((net, truth, info))
    return out
