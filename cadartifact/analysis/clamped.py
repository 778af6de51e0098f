"""Clamped borders on the predicted road: the uniform-equivalent net of a clamped direction (issue 23, item 5).

The predicted road (:func:`cadartifact.analysis.fields.predicted_fields`) synthesises the limit surface of a
uniform net from the scheme's symbols. A face's direction with clamped uniform knots (end multiplicity
``p + 1``) is not the uniform B-spline of its control points near its ends: there the clamped basis
differs from the uniform one. On its domain, though, it is exactly a uniform B-spline of other points:

* the *uniform-equivalent points* ``Q = C P`` (``C`` : ``(n, n)``, the change of basis from the clamped
  B-spline basis to the uniform one on the domain; it differs from the identity only in its first and last
  ``p`` rows) sit on the lattice ``x = k - (p - 1) / 2`` (span units), ``(p - 1) / 2`` beyond each end;
* the uniform B-spline of ``Q`` is the face along this direction, exactly, on ``[0, L]``.

This module reads such a direction from ``Q``: a Legendre polynomial fitted to ``Q`` (its limit is a
polynomial, base band), and the rest continued past the ends by a smooth Hermite bridge on the lattice (value
and :data:`BRIDGE_ORDER` derivatives of the end control polynomial at each end, over a gap of at least
:data:`MIN_GAP` lattice points), whose periodic limit is split by FFT with the scheme's transfer function. The
continuation changes nothing on the domain; it plays the part the measured road's bridge plays there
(:func:`cadartifact.analysis.fields._bridge`). A direction with no ripple band (``AxisFrame.ripple_free``)
gets the face itself as its base band and no ripple.

For a rational face the same operators act on the homogeneous net ``(w P, w)`` (a non-rational B-spline in
four dimensions; SPEC §4). Only rational faces take this road (:func:`clamped_syntheses`); the predicted
road of non-rational and periodic faces is unchanged.
"""

from __future__ import annotations

from math import factorial

import numpy as np

from .frames import AxisFrame
from .intent import Intent, _legendre
from ..net import clamped_uniform_knots, knots_are_uniform
from ..numerics.hermite import hermite_basis
from ..numerics.operator_cache import OperatorCache
from ..numerics.splines import basis_matrix

__all__ = ["clamped_direction", "uniform_equivalent", "lattice_continuation", "clamped_synthesis",
           "clamped_syntheses", "reads_clamped_borders", "MIN_GAP", "BRIDGE_ORDER",
           "MAX_CLAMPED_DEGREE"]

#: Lattice points of the continuation's gap at least (a longer bridge is a smoother one: its own content
#: above half a cycle per point falls with the gap).
MIN_GAP = 30

#: The highest degree the uniform-equivalent reading is checked at (the rational family, degrees 2-4). Above it
#: the change of basis grows fast (its entries about 2e2 at degree 5, 7e5 at 9) and predicted over measured
#: ripple spread 0.03-2.5 on the same family (an independent review, 2026-12-04): such faces keep the caveat.
MAX_CLAMPED_DEGREE = 4

#: Derivatives of the end control polynomial the lattice bridge matches at each end (value and 1..order).
BRIDGE_ORDER = 5


def clamped_direction(net, axis: int, scheme) -> bool:
    """Whether a direction of a face is open with clamped uniform knots, read under its own B-spline degree.

    Parameters
    ----------
    net : ControlNet
    axis : int
        0 (u) or 1 (v).
    scheme : Scheme

    Returns
    -------
    bool
        True when the knots are ``p + 1`` equal end knots at each end and uniform simple interior knots, the
        degree is at most :data:`MAX_CLAMPED_DEGREE`, and ``scheme.degrees[axis]`` is the face's degree (the
        scheme's limit is this B-spline's uniform basis).
    """
    if not net.is_bspline or net.periodic[axis] or getattr(scheme, "degrees", None) is None:
        return False
    p, n = int(net.degrees[axis]), int(net.shape[axis])
    if int(scheme.degrees[axis]) != p or n < p + 1 or p > MAX_CLAMPED_DEGREE:
        return False
    t = np.asarray(net.knots[axis], float)
    scale = max(abs(t[-1] - t[0]), 1e-300)
    ends = np.ptp(t[: p + 1]) <= 1e-12 * scale and np.ptp(t[-p - 1:]) <= 1e-12 * scale
    return bool(ends and knots_are_uniform(t, p))


def _require_net(n, p, minimum_degree: int = 1, exact: bool = True) -> None:
    """A net's size and degree, or a ValueError that says which and what was received."""
    if not isinstance(p, (int, np.integer)) or p < minimum_degree:
        raise ValueError(f"p: expected an integer >= {minimum_degree}, received {p!r}")
    least = p + 1 if exact else 1
    if not isinstance(n, (int, np.integer)) or n < least:
        raise ValueError(f"n: expected an integer >= {least}, received {n!r}")


def _uniform_knots(n: int, p: int) -> np.ndarray:
    """``(n + p + 1,)``: the uniform knots ``-p .. n`` whose domain ``[0, n - p]`` is the clamped one's (spans)."""
    return np.arange(-p, n + 1, dtype=float)


def uniform_equivalent(n: int, p: int) -> np.ndarray:
    """The change from a clamped uniform B-spline's control points to the uniform B-spline's of the same curve.

    On the domain ``[0, n - p]`` (span units)

    .. math:: \\sum_i N^c_i(x) P_i = \\sum_k N^u_k(x) Q_k, \\qquad Q = C P,

    ``N^u_k`` with support ``[k - p, k + 1]``, sitting at ``x = k - (p - 1) / 2``. Exact (to rounding): both
    bases span the same piecewise polynomials on the domain (Curry-Schoenberg); interior functions whose knots
    are all simple are uniform ones, so ``C`` is the identity there.

    Parameters
    ----------
    n : int
        Control points (``>= p + 1``).
    p : int
        Degree (``>= 1``).

    Returns
    -------
    C : (n, n) float

    References
    ----------
    L. Piegl, W. Tiller, *The NURBS Book*, 2nd ed., Springer 1997, ch. 2 (B-spline bases on a knot vector).
    """
    _require_net(n, p)
    spans = n - p
    s = (np.arange(spans)[:, None] + (np.arange(p + 1) + 0.5)[None, :] / (p + 1)).ravel()
    Nc = basis_matrix(clamped_uniform_knots(n, p, 0.0, float(spans)), p, s, n)
    Nu = basis_matrix(_uniform_knots(n, p), p, s, n)
    C = np.linalg.lstsq(Nu, Nc, rcond=None)[0]
    C[np.abs(C) < 1e-14] = 0.0
    # clamped functions whose knots are all simple are uniform ones: identity rows and columns there, exactly
    inner = np.arange(p, n - p)
    C[inner, :] = 0.0
    C[:, inner] = 0.0
    C[inner, inner] = 1.0
    return C


def _end_taylor(n: int, p: int, order: int, at_end: bool) -> np.ndarray:
    """``(order + 1, n)``: lattice values -> value and derivatives ``1..order`` (along ``+x``, per lattice step)
    of the degree-``min(p, n - 1)`` polynomial through the last (first) ``p + 1`` values, at the last (first)
    point. The uniform B-spline of those control points is its end span's polynomial continued."""
    d = min(p, n - 1)
    s = np.arange(-d, 1, dtype=float) if at_end else np.arange(0, d + 1, dtype=float)
    V = s[:, None] ** np.arange(d + 1)[None, :]
    coef = np.linalg.inv(V)  # values -> monomial coefficients about the end point
    out = np.zeros((order + 1, n))
    cols = np.arange(n - d - 1, n) if at_end else np.arange(d + 1)
    for k in range(min(order, d) + 1):
        out[k, cols] = factorial(k) * coef[k]
    return out


def lattice_continuation(n: int, p: int, gap: int, order: int = BRIDGE_ORDER) -> np.ndarray:
    """One period of a lattice continued past its ends: the values, then a Hermite bridge across the gap.

    The bridge (:func:`~cadartifact.numerics.hermite.hermite_basis`, degree ``2 order + 1``) runs from the
    last value's end polynomial (degree ``min(p, n - 1)`` through the last ``p + 1`` values) to the first's,
    matching value and ``order`` derivatives at each end, so the periodic extension has no jump the split
    could read.

    Parameters
    ----------
    n : int
        Lattice points (``>= 1``).
    p : int
        Degree of the end polynomials (``>= 0``).
    gap : int
        Points of the bridge (``>= 0``).
    order : int, optional
        Derivatives matched (default :data:`BRIDGE_ORDER`).

    Returns
    -------
    L : (n + gap, n) float
        Lattice values -> the period's values.
    """
    _require_net(n, p, minimum_degree=0, exact=False)
    if not isinstance(gap, (int, np.integer)) or gap < 0:
        raise ValueError(f"gap: expected an integer >= 0, received {gap!r}")
    G = int(gap)
    Lg = float(G + 1)
    t = np.arange(1, G + 1, dtype=float) / Lg
    H = hermite_basis(t, order)  # (2 order + 2, G)
    scale = Lg ** np.arange(order + 1)
    ends = np.concatenate([_end_taylor(n, p, order, True) * scale[:, None],
                           _end_taylor(n, p, order, False) * scale[:, None]], axis=0)
    return np.vstack([np.eye(n), H.T @ ends])


#: Per direction (geometry, trend degree, levels, scheme, axis, ripple-free): the synthesis operators.
_SYNTHESES = OperatorCache(256)


def clamped_synthesis(frame: AxisFrame, degree: int, trend: int, scheme, axis: int):
    """One clamped direction of a tensor B-spline's limit surface: ``(low, high, low_at)`` (cached; read-only).

    Parameters
    ----------
    frame : AxisFrame
        An open direction of ``n`` points and ``L = n - p`` spans.
    degree : int
        The face's degree ``p`` along it.
    trend : int
        Degree of the Legendre polynomial fitted to the uniform-equivalent points.
    scheme : Scheme
        A tensor B-spline of degree ``p`` along ``axis``.
    axis : int

    Returns
    -------
    low, high : (frame.fine_count, n) float
        Control points -> the base band / the ripple band of the face along this direction on the fine grid.
    low_at : callable
        ``low_at(x)`` : ``(len(x), n)``, the base band at analysis coordinates ``x`` on the domain.
    """
    key = (frame.n, frame.spans, frame.levels, round(frame.offset, 12), frame.ripple_free, degree, trend, scheme, axis)
    return _SYNTHESES.get(key, lambda: _build(frame, degree, trend, scheme, axis))


def _build(frame: AxisFrame, p: int, trend: int, scheme, axis: int):
    n, K, spans = frame.n, frame.K, frame.spans
    clamped = clamped_uniform_knots(n, p, 0.0, float(spans))
    if frame.ripple_free:  # no ripple band: the face itself is the base band
        low = basis_matrix(clamped, p, frame.x, n)
        high = np.zeros_like(low)
        low.flags.writeable = high.flags.writeable = False
        return low, high, lambda x: basis_matrix(clamped, p, np.asarray(x, float), n)
    C = uniform_equivalent(n, p)
    xq = np.arange(n) - (p - 1) / 2.0  # where the uniform-equivalent points sit
    d = int(min(trend, n - 1))
    Vq = _legendre(xq, spans, d)
    Pq = np.linalg.pinv(Vq) @ C  # points -> the polynomial's Legendre samples' coefficients
    rest = C - Vq @ Pq  # points -> what the polynomial leaves of Q
    T = n + max(MIN_GAP, 2 * spans)
    E = lattice_continuation(n, p, T - n) @ rest  # (T, n), row k at x = xq[k] (k >= n: past the end)
    c = int(round((p - 1) / 2.0 + frame.offset))  # xq[0] = -c + offset
    E = np.roll(E, -c, axis=0)  # row j at x = j + offset (mod T)
    X = np.fft.fft(E, axis=0)
    xi = np.fft.fftfreq(K * T, d=1.0 / K)
    zeros = np.zeros_like(xi)
    T1 = np.asarray(scheme.transfer(xi, zeros, frame.levels) if axis == 0 else
                    scheme.transfer(zeros, xi, frame.levels), float)
    spec = np.tile(X, (K, 1)) * (K * T1)[:, None]
    low_bins = np.abs(xi) < 0.5 - 1e-12
    shift = int(round(-frame.offset * K)) % (K * T)
    idx = (shift + np.arange(frame.fine_count)) % (K * T)
    uniform = _uniform_knots(n, p)
    poly_ops = Vq @ Pq  # points -> the polynomial's part of Q; its uniform B-spline is a polynomial

    def poly(x):
        return basis_matrix(uniform, p, np.asarray(x, float), n) @ poly_ops

    low = poly(frame.x) + np.fft.ifft(spec * low_bins[:, None], axis=0).real[idx]
    high = np.fft.ifft(spec * ~low_bins[:, None], axis=0).real[idx]
    Xl, fl = spec[low_bins], xi[low_bins]

    def low_at(x):
        z = np.asarray(x, float) + shift / K
        ph = 2 * np.pi * np.outer(z, fl)
        return poly(x) + (np.cos(ph) @ Xl.real - np.sin(ph) @ Xl.imag) / (K * T)

    low.flags.writeable = high.flags.writeable = False
    return low, high, low_at


def reads_clamped_borders(intent: Intent, scheme) -> bool:
    """Whether the predicted road reads this face's clamped directions from their uniform-equivalent points.

    Parameters
    ----------
    intent : Intent
    scheme : Scheme

    Returns
    -------
    bool
        True for a rational face under a tensor scheme, with at least one open direction and every open
        direction clamped with uniform knots under its own degree, at most :data:`MAX_CLAMPED_DEGREE`
        (:func:`clamped_direction`).
    """
    net = intent.net
    if not intent.homogeneous or not net.is_bspline or not getattr(scheme, "tensor", False):
        return False
    return not all(net.periodic) and all(net.periodic[k] or clamped_direction(net, k, scheme) for k in (0, 1))


def clamped_syntheses(intent: Intent, scheme) -> tuple | None:
    """Per direction of a rational face whose open directions are all clamped (:func:`clamped_direction`),
    ``(low, high, low_at)`` of :func:`clamped_synthesis` for each open direction and ``None`` for a periodic
    one (the caller's uniform synthesis); ``None`` for any other net (the predicted road as before).

    Parameters
    ----------
    intent : Intent
    scheme : Scheme

    Returns
    -------
    tuple of 2 (tuple or None), or None
    """
    if not reads_clamped_borders(intent, scheme):
        return None
    net = intent.net
    out = []
    for k, frame in enumerate(intent.frames):
        if frame.periodic:
            out.append(None)
        else:
            p = int(net.degrees[k])
            out.append(clamped_synthesis(frame, p, p, scheme, k))
    return tuple(out)
