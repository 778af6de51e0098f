"""A face sampled for its product-data-quality criteria (:mod:`cadartifact.analysis.quality`): the quadrature grid of
its trim box, the surface and its partial derivatives there, the curvatures, and the inflections along a line.

Sampling (per direction): the trim box ``[lo, hi]`` is cut at the distinct knots into pieces; each piece gets
``m`` Gauss-Legendre nodes (``m = clip(240 // pieces, 2, 6)``) and the box's ends are added with weight 0, so
that ``sum_i w_i f(u_i)`` integrates a function of the parameter and curvature is seen in every span. The surface
is evaluated in numpy (:func:`cadartifact.numerics.splines.basis_derivatives`; rational faces through their
homogeneous form), never with OCCT.

References: M. P. do Carmo, *Differential Geometry of Curves and Surfaces*, 1976, ch. 3 (fundamental forms,
principal and normal curvatures); L. Piegl, W. Tiller, *The NURBS Book*, 2nd ed., 1997, eq. 4.8.
"""

from __future__ import annotations

import math
from dataclasses import dataclass
from typing import NamedTuple

import numpy as np

__all__ = ["FaceSamples", "Measured", "NotEvaluated", "trim_box", "sample_face", "curvatures", "inflections",
           "direction_range"]


class Measured(NamedTuple):
    """What a measure found: the value, where the face is worst (or None), one line of supporting numbers, and a
    verdict when the measure decides it rather than the thresholds (None: judged against the profile)."""

    value: float
    uv: tuple | None = None
    xyz: tuple | None = None
    detail: str = ""
    verdict: str | None = None


class NotEvaluated(NamedTuple):
    """A measure that cannot be taken on this face, and why."""

    reason: str


@dataclass(frozen=True)
class FaceSamples:
    """A face sampled on the grid ``u x v`` (:func:`sample_face`).

    Attributes
    ----------
    u, v : (a,), (b,) float
        Parameters (increasing; the trim box's ends included).
    wu, wv : (a,), (b,) float
        Quadrature weights: ``sum_i wu_i f(u_i) ~ int f du`` over the box.
    S, Su, Sv, Suu, Suv, Svv : (a, b, 3) float
        The point and its partial derivatives.
    """

    u: np.ndarray
    v: np.ndarray
    wu: np.ndarray
    wv: np.ndarray
    S: np.ndarray
    Su: np.ndarray
    Sv: np.ndarray
    Suu: np.ndarray
    Suv: np.ndarray
    Svv: np.ndarray


def direction_range(t, p: int, n: int, periodic: bool) -> tuple[float, float]:
    """The knot range ``[t_p, t_n]`` of one direction (periodic: one period, ``[t_p, t_(p+n)]``)."""
    return float(t[p]), float(t[n if not periodic else p + n])


def _breaks(t: np.ndarray, p: int, n: int, periodic: bool, lo: float, hi: float) -> np.ndarray:
    """Distinct knots strictly inside ``(lo, hi)`` (a periodic direction: the period's knots repeated)."""
    a, b = direction_range(t, p, n, periodic)
    distinct = np.unique(t[p:(n if not periodic else p + n) + 1])
    if periodic:
        period = b - a
        k0, k1 = math.floor((lo - a) / period) - 1, math.ceil((hi - a) / period) + 1
        distinct = np.unique(np.concatenate([distinct + k * period for k in range(k0, k1 + 1)]))
    tol = 1e-12 * max(1.0, abs(hi - lo), abs(lo), abs(hi))
    return distinct[(distinct > lo + tol) & (distinct < hi - tol)]


_GAUSS = {m: np.polynomial.legendre.leggauss(m) for m in range(2, 7)}


def _nodes(lo: float, hi: float, inner: np.ndarray, cap: int = 240) -> tuple[np.ndarray, np.ndarray]:
    """Gauss-Legendre nodes and weights per piece of ``[lo, hi]`` cut at ``inner``, with the ends (weight 0)."""
    edges = np.concatenate([[lo], inner, [hi]])
    g, w = _GAUSS[int(np.clip(cap // (len(edges) - 1), 2, 6))]
    a, b = edges[:-1, None], edges[1:, None]
    x = (a + (b - a) * (g[None, :] + 1) / 2).ravel()
    wx = ((b - a) / 2 * w[None, :]).ravel()
    return np.concatenate([[lo], x, [hi]]), np.concatenate([[0.0], wx, [0.0]])


def trim_box(net) -> tuple[float, float, float, float]:
    """``uv_bounds`` clipped to the knot range (periodic: not clipped), or the knot range of an untrimmed net."""
    box = []
    for k, (t, p, n, per) in enumerate(zip(net.knots, net.degrees, net.shape, net.periodic)):
        a, b = direction_range(np.asarray(t, float), p, n, per)
        if net.uv_bounds is None:
            box += [a, b]
            continue
        lo, hi = net.uv_bounds[2 * k], net.uv_bounds[2 * k + 1]
        if not per:
            lo, hi = max(lo, a), min(hi, b)
        box += [lo, hi]
    return tuple(box)


def sample_face(net, u: np.ndarray | None = None, v: np.ndarray | None = None) -> FaceSamples:
    """Evaluate a B-spline/NURBS face and its first and second partial derivatives on a grid.

    Parameters
    ----------
    net : ControlNet
        With knots and degrees.
    u, v : (a,), (b,) float, optional
        Parameters (default: the quadrature grid of the trim box, see the module's notes; weights are then
        those of the quadrature, else zero).

    Notes
    -----
    Returns :class:`FaceSamples`. With homogeneous points ``H = (w P, w)`` and ``A = sum_ij N_i(u) N_j(v) H_ij`` (and its derivatives, by
    the derivatives of the basis), ``S = A_xyz / A_w`` and, by the quotient rule (The NURBS Book, eq. 4.8),
    ``S_u = (A_u - w_u S) / w``, ``S_uu = (A_uu - 2 w_u S_u - w_uu S) / w``,
    ``S_uv = (A_uv - w_u S_v - w_v S_u - w_uv S) / w``.
    """
    (ku, kv), (p, q), (pu, pv), (nu, nv) = net.knots, net.degrees, net.periodic, net.shape
    u0, u1, v0, v1 = trim_box(net)
    wu = wv = None
    if u is None:
        u, wu = _nodes(u0, u1, _breaks(np.asarray(ku, float), p, nu, pu, u0, u1))
    if v is None:
        v, wv = _nodes(v0, v1, _breaks(np.asarray(kv, float), q, nv, pv, v0, v1))
    from ..numerics.splines import basis_derivatives

    u, v = np.asarray(u, float), np.asarray(v, float)
    Bu = basis_derivatives(ku, p, u, nu, pu)
    Bv = basis_derivatives(kv, q, v, nv, pv)
    P = np.asarray(net.points, float)
    w = np.ones(P.shape[:2]) if net.weights is None else np.asarray(net.weights, float)
    H = np.concatenate([P * w[:, :, None], w[:, :, None]], axis=-1).reshape(nu, nv * 4)  # (w P, w)
    T = [(Bu[a] @ H).reshape(len(u), nv, 4).transpose(0, 2, 1) for a in range(3)]  # (a, 4, nv)
    A = {(a, b): (T[a] @ Bv[b].T).transpose(0, 2, 1) for a, b in ((0, 0), (1, 0), (0, 1), (2, 0), (1, 1), (0, 2))}
    W = {ab: A[ab][..., 3:] for ab in A}
    X = {ab: A[ab][..., :3] for ab in A}
    w0 = W[0, 0]
    S = X[0, 0] / w0
    Su = (X[1, 0] - W[1, 0] * S) / w0
    Sv = (X[0, 1] - W[0, 1] * S) / w0
    Suu = (X[2, 0] - 2 * W[1, 0] * Su - W[2, 0] * S) / w0
    Svv = (X[0, 2] - 2 * W[0, 1] * Sv - W[0, 2] * S) / w0
    Suv = (X[1, 1] - W[1, 0] * Sv - W[0, 1] * Su - W[1, 1] * S) / w0
    zero_u, zero_v = np.zeros(len(u)), np.zeros(len(v))
    return FaceSamples(u=u, v=v, wu=zero_u if wu is None else wu, wv=zero_v if wv is None else wv, S=S, Su=Su,
                       Sv=Sv, Suu=Suu, Suv=Suv, Svv=Svv)


def curvatures(fs: FaceSamples) -> dict:
    """Normals, principal and isoparametric normal curvatures on the samples.

    Returns
    -------
    dict
        ``"valid"`` (a, b) bool (the normal is defined: ``|S_u x S_v| > 1e-10 |S_u| |S_v|`` and neither
        derivative below 1e-6 of its median over the face: a collapsed edge, such as a sphere's pole),
        ``"kmax"`` (a, b): ``max |k_i| = |H| + sqrt(max(H^2 - K, 0))``, ``"ku"``, ``"kv"`` (a, b): the normal
        curvature along the u and v lines, ``L / E`` and ``N / G``; NaN where not valid.

    Notes
    -----
    First fundamental form ``E = S_u.S_u, F = S_u.S_v, G = S_v.S_v``, second ``L = S_uu.n, M = S_uv.n,
    N = S_vv.n`` with ``n = S_u x S_v / |S_u x S_v|``; ``K = (LN - M^2) / (EG - F^2)``,
    ``H = (EN - 2FM + GL) / (2 (EG - F^2))`` (do Carmo §3.3).
    """
    cross = np.cross(fs.Su, fs.Sv)
    norm = np.linalg.norm(cross, axis=-1)
    lu, lv = np.linalg.norm(fs.Su, axis=-1), np.linalg.norm(fs.Sv, axis=-1)
    # a collapsed edge (a sphere's pole) has one derivative zero up to rounding, and the fundamental forms
    # there are rounding noise: a derivative below 1e-6 of the face's typical one counts as zero
    typical_u = float(np.median(lu)) if lu.size else 0.0
    typical_v = float(np.median(lv)) if lv.size else 0.0
    valid = (lu > 1e-6 * typical_u) & (lv > 1e-6 * typical_v) & (lu > 0) & (lv > 0) & (norm > 1e-10 * lu * lv)
    with np.errstate(divide="ignore", invalid="ignore"):
        n = cross / norm[..., None]
        E, F, G = lu ** 2, np.einsum("abk,abk->ab", fs.Su, fs.Sv), lv ** 2
        L = np.einsum("abk,abk->ab", fs.Suu, n)
        M = np.einsum("abk,abk->ab", fs.Suv, n)
        N = np.einsum("abk,abk->ab", fs.Svv, n)
        det = E * G - F ** 2
        K = (L * N - M ** 2) / det
        H = (E * N - 2 * F * M + G * L) / (2 * det)
        kmax = np.abs(H) + np.sqrt(np.maximum(H ** 2 - K, 0.0))
        ku, kv = L / E, N / G
    nan = np.full(valid.shape, np.nan)
    return {"valid": valid, "kmax": np.where(valid, kmax, nan), "ku": np.where(valid, ku, nan),
            "kv": np.where(valid, kv, nan)}


def inflections(k: np.ndarray, floor: float) -> tuple[int, float, int]:
    """Sign changes of a curvature sequence along one line, ignoring ``|k| <= floor`` (and NaN).

    Returns
    -------
    count : int
        Lobes of one sign minus one (a lobe: consecutive samples of the same sign with ``|k| > floor``).
    amplitude : float
        Largest ``min(peak |k| of the lobe before, peak |k| of the lobe after)`` over the sign changes (0 without).
    at : int
        Index of the first sample after the largest sign change (-1 without).
    """
    k = np.asarray(k, float)
    idx = np.flatnonzero(np.isfinite(k) & (np.abs(k) > floor))
    if len(idx) < 2:
        return 0, 0.0, -1
    s = np.sign(k[idx])
    starts = np.concatenate([[0], np.flatnonzero(np.diff(s) != 0) + 1])
    if len(starts) < 2:
        return 0, 0.0, -1
    peaks = np.maximum.reduceat(np.abs(k[idx]), starts)
    amps = np.minimum(peaks[:-1], peaks[1:])
    best = int(np.argmax(amps))
    return len(starts) - 1, float(amps[best]), int(idx[starts[best + 1]])
