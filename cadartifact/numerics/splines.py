"""Exact tensor-product NURBS evaluation in numpy, and the index <-> parameter maps.

This is the "measured" road for B-spline faces: it evaluates the face's own
knots, degrees and weights (Cox-de Boor), independently of the spectral
formulas. Tests check it against OCCT's evaluator point by point.

References
----------
L. Piegl, W. Tiller, *The NURBS Book*, 2nd ed., Springer 1997, algorithms A2.2 and A4.3.
"""

from __future__ import annotations

from typing import TYPE_CHECKING

import numpy as np

from ..errors import OptionError

if TYPE_CHECKING:  # the data model sits above this wing: a type only, never imported at run time
    from ..net import ControlNet


__all__ = ["basis_derivatives", "basis_matrix", "evaluate", "index_to_param", "param_range", "periodic_greville"]


def param_range(knots: np.ndarray, degree: int) -> tuple[float, float]:
    """The valid parameter interval ``[t_p, t_{m-p-1}]`` of a flat knot vector."""
    t = np.asarray(knots, dtype=float)
    return float(t[degree]), float(t[len(t) - degree - 1])


def _knot_spans(t: np.ndarray, p: int, x, periodic: bool) -> tuple[np.ndarray, np.ndarray, int]:
    """``(x, s, nb)``: parameters clipped to the valid range (periodic: wrapped into it), the span index
    ``s`` with ``t_s <= x < t_{s+1}`` in ``[p, nb - 1]`` (``x == hi`` belongs to the last span), and the
    number ``nb`` of basis functions of the flat sequence."""
    x = np.asarray(x, dtype=float).ravel()
    lo, hi = param_range(t, p)
    if periodic:
        x = lo + np.mod(x - lo, hi - lo)
        x = np.where(np.isclose(x, hi, rtol=0, atol=1e-14 * max(1.0, abs(hi))), lo, x)
    else:
        x = np.clip(x, lo, hi)
    nb = len(t) - p - 1
    return x, np.clip(np.searchsorted(t, x, side="right") - 1, p, nb - 1), nb


def basis_matrix(knots: np.ndarray, degree: int, x: np.ndarray, n: int | None = None,
                 periodic: bool = False) -> np.ndarray:
    """B-spline basis functions evaluated at parameters ``x``.

    Parameters
    ----------
    knots : (m,) float
        Flat knot vector (OCCT's ``KnotSequence``: ``n+p+1`` knots, or ``n+2p+1`` when periodic).
    degree : int
        Degree ``p``.
    x : (k,) float
        Parameters, clipped to the valid range (periodic: wrapped into it).
    n : int, optional
        Number of poles (default ``m - p - 1``, or ``m - 2p - 1`` when periodic).
    periodic : bool
        Periodic spline: the ``n + p`` basis functions of the flat sequence act on poles ``i mod n``.

    Returns
    -------
    B : (k, n) float
        ``B[a, i] = N_{i,p}(x_a)`` (periodic: summed over the wrapped copies of pole ``i``).
        Rows sum to 1.

    Notes
    -----
    Cox-de Boor recursion ``N_{i,p} = (x-t_i)/(t_{i+p}-t_i) N_{i,p-1} + (t_{i+p+1}-x)/(t_{i+p+1}-t_{i+1}) N_{i+1,p-1}``
    with 0/0 = 0, vectorised over ``x`` (The NURBS Book, eq. 2.5).
    """
    t, p = np.asarray(knots, dtype=float), int(degree)
    x, s, nb = _knot_spans(t, p, x, periodic)
    # triangular table N[a, r] for the p+1 non-zero functions s-p .. s (Piegl & Tiller A2.2)
    N = np.zeros((len(x), p + 1))
    N[:, 0] = 1.0
    left = np.zeros((len(x), p + 1))
    right = np.zeros((len(x), p + 1))
    for j in range(1, p + 1):
        left[:, j] = x - t[s + 1 - j]
        right[:, j] = t[s + j] - x
        saved = np.zeros(len(x))
        for r in range(j):
            denom = right[:, r + 1] + left[:, j - r]
            with np.errstate(divide="ignore", invalid="ignore"):
                temp = np.where(denom != 0, N[:, r] / denom, 0.0)
            N[:, r] = saved + right[:, r + 1] * temp
            saved = left[:, j - r] * temp
        N[:, j] = saved
    if n is None:
        n = nb - p if periodic else nb
    B = np.zeros((len(x), n))
    rows = np.repeat(np.arange(len(x)), p + 1)
    cols = (s[:, None] - p + np.arange(p + 1)[None, :]).ravel()
    if periodic:
        cols = np.mod(cols, n)
    elif nb != n:
        raise OptionError("n", f"{nb} poles for {len(t)} knots of degree {p}", n)
    np.add.at(B, (rows, cols), N.ravel())
    return B


def basis_derivatives(knots: np.ndarray, degree: int, x: np.ndarray, n: int | None = None, periodic: bool = False,
                      order: int = 2) -> np.ndarray:
    """B-spline basis functions and their derivatives up to ``order`` at parameters ``x``.

    Parameters
    ----------
    knots, degree, x, n, periodic
        As :func:`basis_matrix`.
    order : int
        Highest derivative wanted (derivatives above the degree are 0).

    Returns
    -------
    D : (order + 1, k, n) float
        ``D[d, a, i] = d^d N_{i,p}(x_a) / dx^d``; at a knot, the derivative of the span on its right (the last
        span's at the range's end). ``D[0]`` equals :func:`basis_matrix`.

    Notes
    -----
    The NURBS Book's algorithm A2.3 (``DersBasisFuns``), vectorised over ``x``: the triangular table of the
    basis functions and knot differences, then ``N^(k)_{r,p} = p!/(p-k)! sum_j a_{k,j} N_{r+j,p-k}`` with the
    coefficients ``a`` of eq. 2.10 built by recurrence.
    """
    t, p = np.asarray(knots, dtype=float), int(degree)
    x, s, nb = _knot_spans(t, p, x, periodic)
    k = len(x)
    ndu = np.zeros((k, p + 1, p + 1))
    ndu[:, 0, 0] = 1.0
    left, right = np.zeros((k, p + 1)), np.zeros((k, p + 1))

    def div(a, b):
        with np.errstate(divide="ignore", invalid="ignore"):
            return np.where(b != 0, a / np.where(b != 0, b, 1.0), 0.0)

    for j in range(1, p + 1):
        left[:, j] = x - t[s + 1 - j]
        right[:, j] = t[s + j] - x
        saved = np.zeros(k)
        for r in range(j):
            ndu[:, j, r] = right[:, r + 1] + left[:, j - r]  # knot differences (lower triangle)
            temp = div(ndu[:, r, j - 1], ndu[:, j, r])
            ndu[:, r, j] = saved + right[:, r + 1] * temp
            saved = left[:, j - r] * temp
        ndu[:, j, j] = saved
    ders = np.zeros((order + 1, k, p + 1))
    ders[0] = ndu[:, :, p]
    for r in range(p + 1):
        a = np.zeros((2, k, p + 1))
        a[0, :, 0] = 1.0
        s1, s2 = 0, 1
        for kk in range(1, min(order, p) + 1):
            d = np.zeros(k)
            rk, pk = r - kk, p - kk
            if r >= kk:
                a[s2, :, 0] = div(a[s1, :, 0], ndu[:, pk + 1, rk])
                d = a[s2, :, 0] * ndu[:, rk, pk]
            j1 = 1 if rk >= -1 else -rk
            j2 = kk - 1 if r - 1 <= pk else p - r
            for j in range(j1, j2 + 1):
                a[s2, :, j] = div(a[s1, :, j] - a[s1, :, j - 1], ndu[:, pk + 1, rk + j])
                d = d + a[s2, :, j] * ndu[:, rk + j, pk]
            if r <= pk:
                a[s2, :, kk] = div(-a[s1, :, kk - 1], ndu[:, pk + 1, r])
                d = d + a[s2, :, kk] * ndu[:, r, pk]
            ders[kk, :, r] = d
            s1, s2 = s2, s1
    factor = p
    for kk in range(1, min(order, p) + 1):
        ders[kk] *= factor
        factor *= p - kk
    if n is None:
        n = nb - p if periodic else nb
    elif not periodic and nb != n:
        raise OptionError("n", f"{nb} poles for {len(t)} knots of degree {p}", n)
    out = np.zeros((order + 1, k, n))
    rows = np.repeat(np.arange(k), p + 1)
    cols = (s[:, None] - p + np.arange(p + 1)[None, :]).ravel()
    if periodic:
        cols = np.mod(cols, n)
    for d in range(order + 1):
        np.add.at(out[d], (rows, cols), ders[d].ravel())
    return out


def evaluate(net: ControlNet, u: np.ndarray, v: np.ndarray, points: np.ndarray | None = None,
             homogeneous: bool = False) -> np.ndarray:
    """Evaluate a B-spline/NURBS net on the outer grid ``u x v``.

    Parameters
    ----------
    net : ControlNet
        With degrees and knots (a cage has no parametrisation: OptionError).
    u : (a,) float
    v : (b,) float
    points : (nu, nv, 3) float, optional
        Other control points on the same knots and weights (the surface is linear in them).
    homogeneous : bool
        ``points`` are homogeneous ``(w P, w)`` ``(nu, nv, 4)``: return the non-rational B-spline of
        them, ``(a, b, 4)`` (the surface in homogeneous coordinates).

    Returns
    -------
    S : (a, b, 3) float
        ``S = sum_ij N_i(u) N_j(v) w_ij P_ij / sum_ij N_i(u) N_j(v) w_ij``.
    """
    if not net.is_bspline:
        raise OptionError("net", "a B-spline net with knots", f"a {net.origin.kind} cage")
    (ku, kv), (p, q), (pu, pv) = net.knots, net.degrees, net.periodic
    nu, nv = net.shape
    Bu = basis_matrix(ku, p, u, nu, pu)
    Bv = basis_matrix(kv, q, v, nv, pv)
    P = net.points if points is None else np.asarray(points, float)
    from .tensor import sandwich

    if net.weights is None or homogeneous:
        return sandwich(Bu, P, Bv)
    w = net.weights
    num = sandwich(Bu, P * w[:, :, None], Bv)
    den = Bu @ w @ Bv.T
    return num / den[:, :, None]


def periodic_greville(knots: np.ndarray, degree: int, n: int) -> np.ndarray:
    """Greville abscissae of the ``n`` poles of a periodic spline, as increasing parameters.

    Pole ``i`` (0-based) drives flat basis functions ``i`` and ``i + n``; its abscissa is that of
    basis function ``i`` wrapped into the valid range, and the result is made increasing by
    unwrapping (it may start below ``t_p``).
    """
    t = np.asarray(knots, dtype=float)
    c = np.concatenate([[0.0], np.cumsum(t)])
    idx = np.arange(n)
    g = (c[idx + degree + 1] - c[idx + 1]) / degree
    return g


def index_to_param(greville: np.ndarray, x: np.ndarray, periodic: bool = False,
                   period: float | None = None) -> np.ndarray:
    """Map index-space coordinates to parameters, piecewise-linearly through the Greville abscissae.

    Parameters
    ----------
    greville : (n,) float
        Increasing abscissae of the poles.
    x : (k,) float
        Index coordinates (pole ``i`` at ``x = i``); periodic: any real, pole ``n`` = pole ``0`` + period.
    periodic : bool
    period : float
        Parameter period (required when periodic).
    """
    g = np.asarray(greville, dtype=float)
    x = np.asarray(x, dtype=float)
    n = len(g)
    if not periodic:
        return np.interp(x, np.arange(n), g)
    if period is None:
        raise OptionError("period", "the parameter period of a periodic direction", None)
    gx = np.concatenate([g, [g[0] + period]])
    k = np.floor(x / n)
    r = x - k * n
    return np.interp(r, np.arange(n + 1), gx) + k * period
